"""Class 5 of issue 27: folders a write created are removed when the command fails or is stopped.

Case ``y-sigint-streamed-json-newdir``: ``plan --pairs ... --json new/sub/out.json`` created
``new/sub`` when it opened its streamed report; Ctrl-C removed the temporary file but left
both folders. Now :func:`csql_sim.infra.files.atomic_output` remembers the folders it
created and removes them (deepest first, each only while empty) when the write fails or is
interrupted; folders that were there before stay.
"""

from __future__ import annotations

import contextlib
import os
import signal
import time
from pathlib import Path

import pytest
from hostile_cli import start

STREAM = ("plan", "--blocks", 12, "--pairs", 1_000_000, "--planner", "gn1", "--json", "new/sub/out.json")
HANG_GUARD = 120.0  # seconds; only against a hang


def _stopped(cwd: Path, sig: int) -> tuple[int, str]:
    """Start the streamed plan, send ``sig`` once it has created ``new/sub``; its exit status and stderr."""
    proc = start(cwd, *STREAM)
    try:
        deadline = time.monotonic() + HANG_GUARD
        while not (cwd / "new" / "sub").is_dir():
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline, "the report was never opened"
            time.sleep(0.01)
        time.sleep(0.3)
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=HANG_GUARD)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    return proc.returncode, err


@pytest.mark.parametrize("sig, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_y_sigint_streamed_json_newdir(work, sig, status):
    code, err = _stopped(work, sig)
    assert code == status, err
    assert not (work / "new").exists(), sorted(p.name for p in (work / "new").rglob("*"))


def test_a_folder_that_was_there_stays(work):
    """Only the folders the command created go: ``new`` existed (with a file), ``new/sub`` did not."""
    (work / "new").mkdir()
    (work / "new" / "keep.txt").write_text("mine\n")
    code, err = _stopped(work, signal.SIGINT)
    assert code == 130, err
    assert sorted(p.name for p in (work / "new").iterdir()) == ["keep.txt"]
