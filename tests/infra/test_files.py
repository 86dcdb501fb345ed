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


# ------------------------------------------------------------------ the output policy (csql_sim.infra.outputs)
def _ours(tmp_path):
    """One file of each kind the tool writes and recognises, by its own header."""
    from csql_sim.core.classifiers.r_classifier import r_classifiers
    from csql_sim.core.files.rulebase import RuleBase, save
    from csql_sim.discovery import transition_log

    rules = RuleBase(3, r_classifiers(3), {"source": "test"})
    made = {"rules.yaml": save(tmp_path / "rules.yaml", rules), "rules.npz": save(tmp_path / "rules.npz", rules)}
    made["t.jsonl"] = transition_log.save(tmp_path / "t.jsonl", [], 3)
    made["r.json"] = write_atomic(tmp_path / "r.json", '{\n "format": "csql-sim states report",\n "version": 1}\n')
    made["d.pddl"] = write_atomic(tmp_path / "d.pddl", "; csql-sim domain, written by csql-sim 0\n(define)\n")
    return made


def test_the_registry_tells_each_format_from_its_first_bytes(tmp_path):
    from csql_sim.infra import formats

    made = _ours(tmp_path)
    assert {name: formats.sniff(path) for name, path in made.items()} == {
        "rules.yaml": formats.RULE_BASE, "rules.npz": formats.RULE_BASE_NPZ, "t.jsonl": formats.TRANSITIONS,
        "r.json": "csql-sim states report", "d.pddl": None}
    assert {name for name, path in made.items() if formats.model_kind(path)} == {"rules.yaml", "rules.npz"}
    for name, text in {"a.yaml": "format: notes\n", "b.json": '{"format": "other"}', "c.txt": ""}.items():
        (tmp_path / name).write_text(text)
        assert formats.sniff(tmp_path / name) is None
    assert formats.sniff(tmp_path / "missing") is None and formats.sniff("/dev/zero") is None


def _outputs(overwrite=False):
    from csql_sim.infra.outputs import Outputs

    return Outputs(overwrite=overwrite)


def test_the_policy_for_existing_files(tmp_path):
    import pytest

    from csql_sim.infra.files import OutputError

    made = _ours(tmp_path)
    (tmp_path / "mine.yaml").write_text("my notes\n")
    fresh = _outputs()
    fresh.file(tmp_path / "new.yaml", "rule file", "rules")  # not there yet
    fresh.check()
    for path, kind, default in ((made["rules.yaml"], "rules", False), (made["r.json"], "json", False),
                                (made["rules.yaml"], "rules", True), (tmp_path / "mine.yaml", "rules", False)):
        existing = _outputs()  # any existing file, ours or not, named or the default: only with --overwrite
        existing.file(path, "output", kind, default=default)
        with pytest.raises(OutputError, match="already exists.*--overwrite"):
            existing.check()
    asked = _outputs(overwrite=True)
    asked.file(tmp_path / "mine.yaml", "rule file", "rules", default=True)
    asked.file(made["r.json"], "JSON report", "json", option="--json")
    asked.check()
    model = _outputs(overwrite=True)  # a report never replaces a model, even with --overwrite
    model.file(made["rules.npz"], "JSON report", "json", option="--json")
    with pytest.raises(OutputError, match="a model is never replaced"):
        model.check()
    assert (tmp_path / "mine.yaml").read_text() == "my notes\n"  # checking writes nothing


def test_the_policy_for_clashes_and_inputs(tmp_path):
    import pytest

    from csql_sim.infra.files import OutputError

    (tmp_path / "in.yaml").write_text("x")
    os.link(tmp_path / "in.yaml", tmp_path / "hard.yaml")
    os.symlink("in.yaml", tmp_path / "soft.yaml")
    for path in ("in.yaml", "hard.yaml", "soft.yaml"):  # the same file by samefile, whatever the name
        plan = _outputs(overwrite=True)
        plan.input(tmp_path / "in.yaml", "rule file")
        plan.file(tmp_path / path, "JSON report", "json", option="--json")
        with pytest.raises(OutputError, match="is the rule file this command reads"):
            plan.check()
    plan = _outputs()
    plan.file(tmp_path / "a" / ".." / "x.json", "JSON report", "json")
    plan.file(tmp_path / "x.json", "log", "transitions")
    with pytest.raises(OutputError, match="are the same path"):
        plan.check()
    plan = _outputs()
    plan.folder(tmp_path / "out", "output folder")
    plan.file(tmp_path / "out", "JSON report", "json")
    with pytest.raises(OutputError, match="are the same path"):
        plan.check()
    plan = _outputs()
    plan.file(tmp_path / "x", "rule file", "rules")
    plan.file(tmp_path / "x" / "t.jsonl", "log", "transitions")
    with pytest.raises(OutputError, match="needs it as a folder"):
        plan.check()
    with pytest.raises(OutputError, match="empty path"):
        _outputs().file("", "rule file", "rules")


# ------------------------------------------------------------------ temporary files and kept copies
def test_stale_temporaries_of_a_dead_process_are_removed(tmp_path):
    from csql_sim.infra.files import remove_stale_temporaries

    dead = subprocess_pid_that_exited()
    stale = tmp_path / f".v.mp4.csql-sim-{dead}-abc.tmp.mp4"
    mine = tmp_path / f".v.mp4.csql-sim-{os.getpid()}-abc.tmp.mp4"  # a live process's
    other = tmp_path / f".w.mp4.csql-sim-{dead}-abc.tmp.mp4"  # another output's
    foreign = tmp_path / ".v.mp4.abc.tmp.mp4"  # not named by us
    for path in (stale, mine, other, foreign):
        path.write_bytes(b"")
        os.utime(path, (1, 1))
    assert remove_stale_temporaries(tmp_path / "v.mp4") == [stale]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in (mine, other, foreign))


def subprocess_pid_that_exited() -> int:
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    return int(proc.stdout)


def test_atomic_output_writes_through_a_symbolic_link(tmp_path):
    (tmp_path / "real.json").write_text("old")
    os.symlink("real.json", tmp_path / "link.json")
    write_atomic(tmp_path / "link.json", "new")
    assert os.readlink(tmp_path / "link.json") == "real.json" and (tmp_path / "real.json").read_text() == "new"


def test_a_copy_that_cannot_be_kept_whole_is_not_kept(tmp_path, monkeypatch):
    import errno
    import tempfile

    import pytest

    from csql_sim.infra.files import OutputError, write_or_keep

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path / "tmp"))
    (tmp_path / "tmp").mkdir()
    (tmp_path / "out").mkdir()

    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)  # every write fails at its end, the kept copy's too
    with pytest.raises(OutputError, match="No space left on device.*no copy of r.yaml could be kept"):
        write_or_keep([(tmp_path / "out" / "r.yaml", "x" * 1000)])
    assert list((tmp_path / "tmp").iterdir()) == [] and list((tmp_path / "out").iterdir()) == []


def test_atomic_output_removes_the_folders_it_created_when_the_write_fails(tmp_path):
    import pytest

    from csql_sim.infra.files import atomic_output

    (tmp_path / "old").mkdir()
    with pytest.raises(KeyboardInterrupt), atomic_output(tmp_path / "old" / "new" / "sub" / "out.json") as tmp:
        tmp.write_text("half")
        raise KeyboardInterrupt
    assert [p.name for p in tmp_path.iterdir()] == ["old"] and list((tmp_path / "old").iterdir()) == []


def test_write_atomic_without_following_links_replaces_the_link_not_its_target(tmp_path):
    import pytest

    from csql_sim.infra.files import OutputError

    (tmp_path / "victim").write_text("precious")
    os.symlink("victim", tmp_path / "ours.bin")
    write_atomic(tmp_path / "ours.bin", "new", follow_links=False)
    assert (tmp_path / "victim").read_text() == "precious"
    assert not (tmp_path / "ours.bin").is_symlink() and (tmp_path / "ours.bin").read_text() == "new"
    (tmp_path / "folder.bin").mkdir()
    with pytest.raises(OutputError, match="folder.bin"):
        write_atomic(tmp_path / "folder.bin", "new", follow_links=False)


def test_load_json_bounds_nesting_and_digits_before_parsing():
    import json

    import pytest

    from csql_sim.infra.files import InputFileError, load_json

    refused = ("[" * 100_000, '{"a": ' * 100_000, "[" * 33 + "]" * 33, "[" + "9" * 5000 + "]", "[-" + "1" * 1001 + "]")
    for text in refused:
        with pytest.raises(InputFileError, match=r"^src\b") as exc:
            load_json(text, "src")
        assert "\n" not in str(exc.value)
    for text in ("[" * 32 + "]" * 32, '["' + "[" * 40 + '\\"[[["]'):  # brackets inside strings do not count
        assert load_json(text, "src") == json.loads(text)
    assert load_json("[" + "9" * 1000 + "]", "src") == [int("9" * 1000)]
    with pytest.raises(InputFileError, match="src is not JSON"):
        load_json('"\\"' * 50_000, "src")  # many unterminated strings: still linear
