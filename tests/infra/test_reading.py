"""InputFile: one open, the head first, then the rest under a cap known only after the head."""

import os

import pytest

from csql_sim.infra.reading import InputFile, InputFileError


def test_the_head_then_the_rest_in_one_open(tmp_path, monkeypatch):
    path = tmp_path / "f.txt"
    path.write_bytes(b"0123456789" * 10)
    opens = []
    os_open = os.open
    monkeypatch.setattr(os, "open", lambda *a, **k: opens.append(a[0]) or os_open(*a, **k))
    with InputFile(path, "rule file", 8) as source:
        assert source.head == b"01234567" and source.size == 100
        assert source.read_all(100) == path.read_bytes()
    assert opens == [path]


def test_a_cap_below_the_size_is_refused_before_reading_on(tmp_path):
    path = tmp_path / "f.txt"
    path.write_bytes(b"x" * 100)
    with InputFile(path, "rule file", 4) as source, \
            pytest.raises(InputFileError, match=r"f.txt: 100 bytes, above the 99-byte limit for a lifted file$"):
        source.read_all(99, "lifted file")


def test_what_cannot_be_opened_is_one_line(tmp_path):
    with pytest.raises(InputFileError, match=r"absent: no such rule file$"):
        InputFile(tmp_path / "absent", "rule file")
    with pytest.raises(InputFileError, match=r"a folder, not a regular rule file$"):
        InputFile(tmp_path, "rule file")
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    with pytest.raises(InputFileError, match=r"a device, pipe or socket, not a regular rule file$"):
        InputFile(fifo, "rule file", 16)  # opened without blocking, never read
