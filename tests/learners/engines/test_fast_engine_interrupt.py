"""The fast engine returns to Python between bounded compiled calls: Ctrl-C stops a long run.

The pauses must not change the trajectory: a run cut into calls of a few steps writes the
same rule file as one in calls of the default size.
"""

import contextlib
import os
import signal
import subprocess
import sys
import time

import pytest

from csql_sim.core.files.rulebase import dumps
from csql_sim.learners.engines import fast_engine
from csql_sim.learners.training.tabular import make_learner, train

HANG_GUARD = 90.0  # seconds; only against a hang (a run of 10**9 trials takes many minutes), never the assertion


def test_tiny_compiled_calls_give_the_same_rule_file_and_curve(monkeypatch):
    over = {"sweep_backup_all": True, "sweep_greedy_tail": 1}
    whole = train("cs-ql", 300, seed=4, params=over, engine="fast")
    a = make_learner("cs-ql", seed=6, engine="fast")
    curve = a.train(200)
    calls = []
    kernels = fast_engine.fk.run_trials  # the compiled function (the module attribute is looked up lazily)
    monkeypatch.setattr(fast_engine, "STEPS_PER_CALL", 7)
    monkeypatch.setattr(fast_engine.fk, "run_trials", lambda *args: calls.append(1) or kernels(*args), raising=False)
    assert dumps(train("cs-ql", 300, seed=4, params=over, engine="fast")) == dumps(whole)
    b = make_learner("cs-ql", seed=6, engine="fast")
    assert b.train(200) == curve and b.t == a.t
    assert len(calls) > 100  # it did pause, between trials, many times


def _mapped(pid: int, name: str) -> bool:
    try:
        with open(f"/proc/{pid}/maps") as fh:
            return name in fh.read()
    except OSError:
        return False


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_ctrl_c_stops_a_long_fast_training_run(tmp_path):
    proc = subprocess.Popen([sys.executable, "-m", "csql_sim", "train", "--trials", "1000000000", "--out", "r.yaml",
                             "--quiet"], cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        deadline = time.monotonic() + HANG_GUARD
        while not _mapped(proc.pid, "llvmlite"):  # numba is imported when the fast engine is built
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline, "training never started"
            time.sleep(0.1)
        time.sleep(2.0)  # well into the compiled training loop
        assert proc.poll() is None
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=HANG_GUARD)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    assert proc.returncode == 130
    assert len(err.splitlines()) == 1 and out == ""
    assert os.listdir(tmp_path) == []
