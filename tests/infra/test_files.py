import os
import stat

from csql_sim.infra.files import write_atomic


def test_write_atomic_replaces_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "sub" / "out.txt"
    write_atomic(target, "first\n")
    write_atomic(target, "second\n")
    assert target.read_text() == "second\n"
    assert [p.name for p in target.parent.iterdir()] == ["out.txt"]


def test_write_atomic_uses_ordinary_permissions(tmp_path):
    umask = os.umask(0o022)
    try:
        path = write_atomic(tmp_path / "f.yaml", "x")
    finally:
        os.umask(umask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644


def test_atomic_output_keeps_the_old_file_when_the_writer_fails(tmp_path):
    from csql_sim.infra.files import atomic_output

    target = tmp_path / "fig.png"
    target.write_text("old")
    try:
        with atomic_output(target) as tmp:
            assert tmp.suffix == ".png" and tmp.parent == tmp_path
            tmp.write_text("half")
            raise RuntimeError("writer crashed")
    except RuntimeError:
        pass
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["fig.png"]


def test_write_atomic_refuses_a_device_node():
    import pytest

    from csql_sim.infra.files import OutputError

    with pytest.raises(OutputError, match="is a device, pipe or socket"):
        write_atomic("/dev/null", "x")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_preflight_checks_create_nothing(tmp_path):
    import pytest

    from csql_sim.infra.files import OutputError, check_output_file, check_output_folder

    assert check_output_file(tmp_path / "new" / "deeper" / "r.yaml") == tmp_path / "new" / "deeper" / "r.yaml"
    assert check_output_folder(tmp_path / "fig") == tmp_path / "fig"
    assert list(tmp_path.iterdir()) == []
    (tmp_path / "f").write_text("")
    with pytest.raises(OutputError, match="exists and is not a folder"):
        check_output_folder(tmp_path / "f")
    with pytest.raises(OutputError, match="is a folder"):
        check_output_file(tmp_path)
    with pytest.raises(OutputError, match="empty path"):
        check_output_file("")


def test_write_or_keep_keeps_every_unwritten_output(tmp_path):
    import pytest

    from csql_sim.infra.files import OutputError, write_or_keep

    (tmp_path / "afile").write_text("")
    with pytest.raises(OutputError) as info:  # a file where the folder should be: both writes fail
        write_or_keep([(tmp_path / "afile" / "a.csv", "1,2\n"), (tmp_path / "afile" / "b.png", b"\x89PNG")])
    kept = str(info.value).split("the results are kept in ", 1)[1].split(", ")
    assert [open(k, "rb").read() for k in kept] == [b"1,2\n", b"\x89PNG"]
    assert kept[0].endswith("-a.csv") and kept[1].endswith("-b.png")
    for k in kept:
        os.unlink(k)


def test_read_text_file_refuses_fifos_without_blocking(tmp_path):
    import pytest

    from csql_sim.infra.files import InputFileError, read_text_file

    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    with pytest.raises(InputFileError, match="a device, pipe or socket, not a regular rule file"):
        read_text_file(fifo, 100, "rule file")
    (tmp_path / "latin1.yaml").write_bytes(b"caf\xe9")
    with pytest.raises(InputFileError, match="not UTF-8 text"):
        read_text_file(tmp_path / "latin1.yaml", 100)
