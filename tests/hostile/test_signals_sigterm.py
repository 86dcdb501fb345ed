"""Class 4 (signals): SIGTERM during sharded training (case ``shtr-sigterm``).

The crash (exit -11, about one run in 75 under load) came from numba's unboxing of a
``numpy.random.Generator``: it calls ``ctypes.cast``, a Python function, without checking
the result, so a signal handler raising there (``Terminated``, ``KeyboardInterrupt``) made
it read through a NULL pointer. :func:`csql_sim.learners.engines.fast_engine.call_kernel` holds the
handlers back for each compiled call. The end-to-end test hits that window rarely; the
storm test hits it within a second on the unfixed engine.
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from hostile_cli import Run, environment, start

TRAIN = ("train", "--quiet", "--blocks", 4, "--shards", 4, "--workers", 1, "--out", "sh")
HANG_GUARD = 120.0  # seconds; only against a hang


def _first_shard(proc: subprocess.Popen, out: Path) -> None:
    """Wait (polling quickly) until a shard file is in ``out`` or the command has ended."""
    deadline = time.monotonic() + HANG_GUARD
    while proc.poll() is None:
        with contextlib.suppress(OSError):
            if any(n.startswith("shard-") and n.endswith(".bin") for n in os.listdir(out)):
                return
        assert time.monotonic() < deadline, "no shard written"
        time.sleep(0.001)


def _terminated_run(cwd: Path) -> Run | None:
    """Start the training, SIGTERM it right after its first shard; None if it ended before the signal."""
    proc = start(cwd, *TRAIN)
    try:
        _first_shard(proc, cwd / "sh")
        if proc.poll() is not None:
            return None
        proc.send_signal(signal.SIGTERM)
        out, err = proc.communicate(timeout=HANG_GUARD)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    return None if proc.returncode == 0 else Run(proc.returncode, out, err)


def test_shtr_sigterm(work: Path):
    interrupted = 0
    for attempt in range(15):
        if interrupted == 5:
            break
        cwd = work / f"run{attempt}"
        cwd.mkdir()
        run = _terminated_run(cwd)
        if run is None:  # finished before the signal: nothing to check
            continue
        interrupted += 1
        assert run.returncode == 128 + signal.SIGTERM, (run.returncode, run.stderr)
        assert run.one_line().startswith("csql-sim: terminated"), run.stderr
        left = [n for n in os.listdir(cwd / "sh") if not (n.startswith("shard-") or n.endswith(".json"))]
        assert left == [], left
    assert interrupted >= 3, "the runs ended before SIGTERM reached them"


STORM = """
import os, signal, sys, threading, time
import numpy as np
from csql_sim.learners.engines.fast_engine import FastCSQL
from csql_sim.learners.paper.params import resolve_params

class Stop(Exception):
    pass

armed = done = False

def handler(signum, frame):
    global armed
    if armed:
        armed = False
        raise Stop

def storm():
    while not done:
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.00005)

learner = FastCSQL(3, resolve_params("cs-ql", None, 3), np.random.default_rng(0))
learner.run_trial(0, 1, 1.0)
signal.signal(signal.SIGTERM, handler)
threading.Thread(target=storm, daemon=True).start()
calls = caught = 0
end = time.monotonic() + float(sys.argv[1])
while True:
    armed = False
    try:
        if time.monotonic() > end:
            done = True
            signal.signal(signal.SIGTERM, signal.SIG_IGN)
            break
        armed = True
        learner.run_trial(calls % 13, 5, 1.0)
        armed = False
        calls += 1
    except Stop:
        caught += 1
print(calls, caught)
"""


def test_shtr_sigterm_kernel_storm(work: Path):
    """SIGTERM every 50 us, its handler raising, while the engine calls its kernels: no crash, and it interrupts."""
    done = subprocess.run([sys.executable, "-c", STORM, "2"], cwd=work, stdin=subprocess.DEVNULL,
                          capture_output=True, text=True, env=environment(work), timeout=HANG_GUARD)
    assert done.returncode == 0, (done.returncode, done.stderr[-2000:])
    calls, caught = map(int, done.stdout.split())
    assert calls > 0 and caught > 0
