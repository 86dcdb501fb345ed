"""Ctrl-C during ``execute --video`` (issue 27, class 4, case ``ex-video-sigint``).

A Ctrl-C reaches the whole process group. The rendering workers (spawned for the EGL
renderer) took it while still importing, before their initializer ignores SIGINT, and
printed a KeyboardInterrupt traceback above "csql-sim: interrupted". Workers now start
with SIGINT blocked (:func:`csql_sim.infra.workers.worker_pool`); the encoder (ffmpeg)
runs in a session of its own and is killed by the writer.
"""

from __future__ import annotations

import os
import signal
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from hostile_cli import start
from video_cases import only_fixtures_left, put_fixtures

EXECUTE = ("execute", "--quiet", "--problem", "ok3.pddl", "--plan", "good.plan", "--out", "v.mp4", "--workers", "2")
# --workers 2: rendering workers even for a short video (the flat painter paints fewer than 150 frames in-process)
HANG_GUARD = 240.0  # seconds for the child process to appear; only against a hang
IMPORTING_SECONDS = 0.3  # into a spawned worker's start-up: still importing, SIGINT not yet ignored
STOP_SECONDS = 10.0  # a Ctrl-C stops the command within this (a second or two when the machine is idle)


def _children(pid: int) -> list[int]:
    """The processes started by any thread of ``pid`` (Linux /proc)."""
    found = []
    for task in Path(f"/proc/{pid}/task").glob("*"):
        try:
            found += [int(c) for c in (task / "children").read_text().split()]
        except OSError:
            continue
    return found


def _cmdline(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
    except OSError:
        return ""


def _catches_sigint(pid: int) -> bool:
    """Whether ``pid`` has a SIGINT handler installed: a Python child past its start-up."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    caught = next((line.split()[1] for line in status.splitlines() if line.startswith("SigCgt:")), "0")
    return bool(int(caught, 16) & (1 << (signal.SIGINT - 1)))


def _render_worker(pid: int) -> int | None:
    """A rendering worker of ``pid`` that runs Python (not the EGL probe, not multiprocessing's tracker)."""
    for child in _children(pid):
        cmd = _cmdline(child)
        if "probe_egl" not in cmd and "resource_tracker" not in cmd and "ffmpeg" not in cmd and _catches_sigint(child):
            return child
    return None


def _encoder(pid: int) -> int | None:
    """The ffmpeg that ``pid`` feeds frames."""
    return next((child for child in _children(pid) if "ffmpeg" in _cmdline(child)), None)


def _wait_for(proc: subprocess.Popen, find: Callable[[int], int | None]) -> int:
    deadline = time.monotonic() + HANG_GUARD
    while proc.poll() is None and time.monotonic() < deadline:
        found = find(proc.pid)
        if found is not None:
            return found
        time.sleep(0.01)
    proc.kill()
    out, err = proc.communicate()
    pytest.fail(f"no such child process appeared (exit {proc.returncode}): {err}")


def _interrupt(proc: subprocess.Popen, child: int, folder: Path, fixtures: dict[str, bytes]) -> None:
    """Ctrl-C to the process group; assert one line, exit 130 within seconds, ``child`` gone, nothing left."""
    began = time.monotonic()
    os.killpg(proc.pid, signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=STOP_SECONDS)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        pytest.fail(f"still running {STOP_SECONDS} s after Ctrl-C")
    assert (proc.returncode, err) == (130, "csql-sim: interrupted\n"), err
    assert time.monotonic() - began < STOP_SECONDS
    deadline = time.monotonic() + 3.0
    while Path(f"/proc/{child}").exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not Path(f"/proc/{child}").exists(), _cmdline(child)
    only_fixtures_left(folder, fixtures)


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="one core: the frames are rendered in-process, no workers")
def test_ex_video_sigint(work):
    """Ctrl-C while a rendering worker starts up (imports): it used to print a traceback."""
    fixtures = put_fixtures(work)
    proc = start(work, *EXECUTE)
    worker = _wait_for(proc, _render_worker)
    time.sleep(IMPORTING_SECONDS)
    _interrupt(proc, worker, work, fixtures)


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="one core: the frames are rendered in-process, no workers")
def test_ex_video_sigint_reaching_a_starting_worker_is_ignored(work):
    """The root, deterministically: a SIGINT that reaches a worker still starting up no longer ends it.

    (Before, the worker died with a KeyboardInterrupt traceback, and the pool with it.)
    """
    proc = start(work, "render", "--quiet", "--start", "CBA", "--goal", "BAC", "--out", "v.mp4", "--width", 64,
                 "--height", 48, "--fps", 5, "--workers", 2)
    os.kill(_wait_for(proc, _render_worker), signal.SIGINT)
    _, err = proc.communicate(timeout=HANG_GUARD)
    assert proc.returncode == 0, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert (work / "v.mp4").stat().st_size > 0


def test_ex_video_sigint_while_encoding(work):
    """Ctrl-C while ffmpeg encodes: it is killed, its temporary video removed, one line."""
    fixtures = put_fixtures(work)
    proc = start(work, *EXECUTE)
    _interrupt(proc, _wait_for(proc, _encoder), work, fixtures)
