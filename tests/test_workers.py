"""Processes: Ctrl-C stops at once, workers die with their parent, no orphans."""

import os
import signal
import subprocess
import sys
import time

import pytest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")


def children(pid: int) -> set[int]:
    """Pids whose parent is ``pid``."""
    found = set()
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as fh:
                    fields = fh.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid and fields[0] != "Z":
                found.add(int(entry))
    return found


def alive(pids: set[int]) -> set[int]:
    """The pids of ``pids`` still running (zombies count as gone)."""
    out = set()
    for pid in pids:
        try:
            with open(f"/proc/{pid}/stat") as fh:
                if fh.read().rsplit(")", 1)[1].split()[0] != "Z":
                    out.add(pid)
        except OSError:
            pass
    return out


def start(tmp_path, *argv):
    """Start ``csql-sim argv`` in its own session; wait until its two workers run."""
    proc = subprocess.Popen([sys.executable, "-m", "csql_sim", *argv], cwd=tmp_path, start_new_session=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while len(children(proc.pid)) < 2:
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, "workers never started"
        time.sleep(0.1)
    time.sleep(0.5)  # let the workers get into their tasks
    return proc, children(proc.pid)


def wait_gone(pids: set[int], seconds: float) -> float:
    began = time.monotonic()
    while alive(pids) and time.monotonic() - began < seconds:
        time.sleep(0.05)
    return time.monotonic() - began


EXPERIMENT = ("experiment", "--cycles", "20", "--trials", "2500", "--workers", "2", "--out", "fig")


def test_ctrl_c_stops_experiment_within_seconds(tmp_path):
    proc, workers = start(tmp_path, *EXPERIMENT)
    began = time.monotonic()
    os.killpg(proc.pid, signal.SIGINT)  # what a terminal's Ctrl-C does: the whole foreground group
    out, err = proc.communicate(timeout=30)
    stopped = time.monotonic() - began
    assert proc.returncode == 130
    assert err == "csql-sim: interrupted\n"  # no worker traceback, no banner
    assert stopped < 3.0, f"took {stopped:.1f} s to stop"
    assert not alive(workers) and not (tmp_path / "fig").exists()


@pytest.mark.parametrize(("argv", "sig"), [
    (EXPERIMENT, signal.SIGKILL),
    (EXPERIMENT, signal.SIGTERM),
    (("evaluate", "--pairs", "40", "--workers", "2", "--quiet"), signal.SIGKILL),
])
def test_workers_die_with_their_parent(tmp_path, argv, sig):
    proc, workers = start(tmp_path, *argv)
    os.kill(proc.pid, sig)  # the main process only, as a crash or an OOM kill would
    proc.communicate(timeout=30)
    assert wait_gone(workers, 5.0) < 5.0, f"orphans left: {alive(workers)}"


@pytest.mark.slow
def test_render_workers_and_encoder_die_with_their_parent(tmp_path):
    proc, workers = start(tmp_path, "render", "--start", "CBA", "--goal", "BAC", "--out", "v.mp4", "--width", "320",
                          "--height", "240", "--workers", "2", "--quiet")
    os.kill(proc.pid, signal.SIGKILL)
    proc.communicate(timeout=30)
    assert wait_gone(workers, 5.0) < 5.0, f"orphans left: {alive(workers)}"
