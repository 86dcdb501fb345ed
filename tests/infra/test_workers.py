"""Processes: Ctrl-C stops at once, workers die with their parent, no orphans.

A cycle of :data:`EXPERIMENT` lasts many minutes, far beyond :data:`HANG_GUARD`: a command or
worker that finished its running task, let alone its queue, would trip the guard. The
guard only stops a hung test; the assertions are on what ran and what is left.
"""

import contextlib
import os
import select
import signal
import subprocess
import sys
import threading
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


HANG_GUARD = 180.0  # seconds; only against a hang, never the assertion (a loaded machine starts workers slowly)


@pytest.fixture
def start(tmp_path):
    """``start(*argv)``: run ``csql-sim argv`` in its own session, wait until its two workers run.

    At teardown, whatever is left of each session started is killed: a failed test leaves
    no experiment running.
    """
    started = []

    def start_(*argv):
        proc = subprocess.Popen([sys.executable, "-m", "csql_sim", *argv], cwd=tmp_path, start_new_session=True,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        started.append(proc)
        deadline = time.monotonic() + HANG_GUARD
        while len(children(proc.pid)) < 2:
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline, "workers never started"
            time.sleep(0.1)
        time.sleep(0.5)  # let the workers get into their tasks
        return proc, children(proc.pid)

    yield start_
    for proc in started:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()


def wait_gone(pids: set[int], within: float = HANG_GUARD) -> set[int]:
    """The pids of ``pids`` still alive once all are gone or ``within`` seconds have passed."""
    deadline = time.monotonic() + within
    while alive(pids) and time.monotonic() < deadline:
        time.sleep(0.05)
    return alive(pids)


# 20 cycles of 50 million trials each: one cycle takes many minutes, so none can finish during a test
EXPERIMENT = ("experiment", "--cycles", "20", "--trials", "50000000", "--workers", "2", "--out", "fig")


def test_ctrl_c_stops_experiment_in_the_middle_of_its_cycles(tmp_path, start):
    proc, workers = start(*EXPERIMENT)
    os.killpg(proc.pid, signal.SIGINT)  # what a terminal's Ctrl-C does: the whole foreground group
    out, err = proc.communicate(timeout=HANG_GUARD)  # waiting for a running cycle would trip this guard
    assert proc.returncode == 130
    assert err == "csql-sim: interrupted\n"  # no worker traceback, no banner
    # Gone by then, or a moment later (a spawned pool's resource tracker ends once the command has
    # closed its pipe): ended mid-cycle, not after it
    assert wait_gone(workers, within=2.0) == set()
    assert not (tmp_path / "fig").exists()  # nothing written


@pytest.mark.parametrize(("argv", "sig"), [
    (EXPERIMENT, signal.SIGKILL),
    (EXPERIMENT, signal.SIGTERM),
    (("evaluate", "--pairs", "40", "--workers", "2", "--quiet"), signal.SIGKILL),
])
def test_workers_die_with_their_parent(start, argv, sig):
    proc, workers = start(*argv)
    os.kill(proc.pid, sig)  # the main process only, as a crash or an OOM kill would
    proc.communicate(timeout=HANG_GUARD)
    assert wait_gone(workers) == set(), "orphans left"  # left alone, they would outlast the guard


@pytest.mark.slow
def test_render_workers_and_encoder_die_with_their_parent(start):
    proc, workers = start("render", "--start", "CBA", "--goal", "BAC", "--out", "v.mp4", "--width", "320",
                          "--height", "240", "--workers", "2", "--quiet")
    os.kill(proc.pid, signal.SIGKILL)
    proc.communicate(timeout=HANG_GUARD)
    assert wait_gone(workers) == set(), "orphans left"


# A pool started beside another thread: that thread holds LOCK while the pool starts. A worker
# forked then would find LOCK held for ever (the hang a fork beside Ray's threads risked).
PROBE = '''
import multiprocessing, os, sys, threading, time
from csql_sim.infra.workers import worker_pool

LOCK = threading.Lock()

def report_and_block(_):
    got = LOCK.acquire(timeout=5)
    os.write(1, f"{os.getpid()} {got}\\n".encode())  # one write: two workers' lines never interleave
    time.sleep(3600)

def main(method):
    release = threading.Event()
    held = threading.Event()
    def hold():
        with LOCK:
            held.set()
            release.wait()
    threading.Thread(target=hold).start()
    held.wait()
    with worker_pool(2, mp_context=multiprocessing.get_context(method) if method else None) as pool:
        futures = [pool.submit(report_and_block, k) for k in range(2)]
        release.set()
        for future in futures:
            future.result()
'''


@pytest.mark.parametrize("method", ["", "forkserver"])  # the default (chosen), or a forkserver named
def test_a_pool_beside_another_thread_is_not_forked_and_its_workers_die_with_it(tmp_path, method):
    (tmp_path / "probe.py").write_text(PROBE)
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), root])}
    proc = subprocess.Popen([sys.executable, "-c", f"import probe; probe.main({method!r})"], env=env, cwd=tmp_path,
                            start_new_session=True, stdout=subprocess.PIPE, text=True)
    try:
        lines = []
        deadline = time.monotonic() + HANG_GUARD
        while len(lines) < 2 and time.monotonic() < deadline:
            if select.select([proc.stdout], [], [], 0.1)[0]:
                lines.append(proc.stdout.readline().split())
        assert all(len(line) == 2 for line in lines), lines  # "pid got", one line per worker
        assert [got for _, got in lines] == ["True", "True"], lines  # LOCK free: a fresh process, not a fork
        workers = {int(pid) for pid, _ in lines}
        assert len(workers) == 2 and proc.poll() is None
        os.kill(proc.pid, signal.SIGKILL)  # the main process only
        proc.wait()
        assert wait_gone(workers) == set(), "orphans left"
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        proc.stdout.close()


def test_an_experiment_gives_the_same_csv_whether_its_workers_are_forked_or_spawned():
    from csql_sim.jobs.experiment import csv_text, run_experiment

    kwargs = {"methods": ("cs-bb-bz", "lt-ql"), "cycles": 3, "trials": 150, "seed": 4, "workers": 2}
    forked = csv_text(run_experiment(**kwargs))
    release = threading.Event()
    beside = threading.Thread(target=release.wait)  # the pool spawns its workers while this runs
    beside.start()
    try:
        spawned = csv_text(run_experiment(**kwargs))
    finally:
        release.set()
        beside.join()
    assert spawned == forked and len(forked.splitlines()) == 1 + 2 * 4
