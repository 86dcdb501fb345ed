"""Ray's failure modes end in one line, and a local instance's processes end with ours.

Found by a hostile-input sweep: after SIGKILL of ``evaluate --backend ray`` the Ray
agents outlived it by a minute; SIGTERM printed a stack dump (later, once in CI, Ray's
C++ core aborted when a cancel raced a finishing task). The hang guards only stop a hung
test; the assertions are on exit status, stderr lines and the processes left.
"""

import contextlib
import importlib.util
import os
import signal
import subprocess
import sys
import time

import pytest

from csql_sim.infra import backends
from csql_sim.infra.backends import Backend, map_tasks
from csql_sim.infra.workers import worker_count

HANG_GUARD = 60.0  # seconds; only against a hang
GONE_GUARD = 20.0  # seconds for what a killed driver left to go (Ray's own agents took a minute)
linux = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
needs_ray = pytest.mark.skipif(importlib.util.find_spec("ray") is None, reason="the ray extra is not installed")


def session(sid: int) -> dict[int, str]:
    """``pid -> command line`` of the live processes of session ``sid``."""
    found = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as fh:
                    fields = fh.read().rsplit(")", 1)[1].split()
                with open(f"/proc/{entry}/cmdline", "rb") as fh:
                    cmd = fh.read().replace(b"\0", b" ").decode(errors="replace").strip()
            except OSError:
                continue
            if int(fields[3]) == sid and fields[0] != "Z":
                found[int(entry)] = cmd
    return found


def wait_for(predicate, guard: float, what: str) -> None:
    deadline = time.monotonic() + guard
    while not predicate():
        assert time.monotonic() < deadline, what
        time.sleep(0.1)


@pytest.fixture
def started():
    """Processes started in sessions of their own; at teardown whatever is left of each session is killed."""
    procs = []
    yield procs
    for proc in procs:
        for pid in session(proc.pid):
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
        with contextlib.suppress(OSError):
            proc.kill()
        proc.wait()


CLUSTER = """
import json, logging, subprocess, sys, ray
ray.init(num_cpus=1, include_dashboard=False, logging_level=logging.ERROR, log_to_driver=False)
address = ray.get_runtime_context().gcs_address  # joinable by this process's children (they inherit its token)
out = subprocess.run([sys.executable, "-m", "csql_sim", "evaluate", "--backend", "ray", "--address", address,
                      "--pairs", "2", "--quiet"], capture_output=True, text=True)
ray.shutdown()
print(json.dumps([out.returncode, out.stdout, out.stderr]))
"""


@linux
@needs_ray
@pytest.mark.slow
def test_a_running_cluster_is_reached_by_its_address(started):
    import json

    cluster = subprocess.Popen([sys.executable, "-c", CLUSTER], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                               text=True, start_new_session=True)
    started.append(cluster)
    status, out, err = json.loads(cluster.communicate(timeout=2 * HANG_GUARD)[0])
    assert status == 0 and err == "" and "episodes: 2" in out, err


# ------------------------------------------------------------------ workers: at most the cores
def test_workers_are_capped_at_the_cores_and_the_tasks(monkeypatch):
    monkeypatch.setattr("os.cpu_count", lambda: 2)
    assert worker_count(1000, 462) == 2 and worker_count(1000, 1) == 1 and worker_count(None, 462) == 2
    assert worker_count(1, 462) == 1


def test_a_thousand_workers_start_a_pool_of_the_cores(monkeypatch):
    from csql_sim.core.state.notation import parse_config

    asked = []
    real = backends.worker_pool
    monkeypatch.setattr("os.cpu_count", lambda: 2)
    monkeypatch.setattr(backends, "worker_pool", lambda n, *a, **k: asked.append(n) or real(n, *a, **k))
    configs = ["AB,C", "CBA", "C,B,A", "BA,C"] * 3
    assert map_tasks(parse_config, configs, Backend("processes", 1000)) == [parse_config(c) for c in configs]
    assert asked == [2]


# ------------------------------------------------------------------ the reaper, without Ray
DRIVER = """
import subprocess, sys, time
from csql_sim.infra.workers import reaper
before = subprocess.Popen(["sleep", "300"])
with reaper():
    inside = subprocess.Popen(["sleep", "300"])
    print(before.pid, inside.pid, flush=True)
    time.sleep(300)
"""


@linux
def test_what_a_killed_process_started_under_the_reaper_ends_with_it(started):
    proc = subprocess.Popen([sys.executable, "-c", DRIVER], stdout=subprocess.PIPE, text=True, start_new_session=True)
    started.append(proc)
    before, inside = map(int, proc.stdout.readline().split())
    time.sleep(1.0)  # the reaper records what runs below its parent four times a second
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    wait_for(lambda: inside not in session(proc.pid), GONE_GUARD, "the process started inside the block survived")
    assert before in session(proc.pid), "a process started before the block is not the reaper's"
    wait_for(lambda: set(session(proc.pid)) == {before}, GONE_GUARD, "the reaper did not exit")


# ------------------------------------------------------------------ a local instance (slow: a Ray start-up each)
def _start_evaluate(started, running: str = "ray::_run_chunk") -> subprocess.Popen:
    """``evaluate --backend ray --pairs all`` in a session of its own, once a process named ``running`` runs in it.

    ``ray::_run_chunk``: its Ray tasks run (and a second later, Ray's agents are up and the
    reaper has seen them); ``gcs_server``: ``ray.init`` is under way.
    """
    proc = subprocess.Popen([sys.executable, "-m", "csql_sim", "evaluate", "--backend", "ray", "--pairs", "all",
                             "--workers", "2", "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    started.append(proc)
    deadline = time.monotonic() + HANG_GUARD
    while not any(running in cmd for cmd in session(proc.pid).values()):
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, f"{running} never started"
        time.sleep(0.05)
    if running == "ray::_run_chunk":
        time.sleep(1.0)
    return proc


SIGNALS = [  # what runs when the signal comes, whom it goes to, the exit status and the one line; before:
    # Ray reported the SIGTERM as a KeyboardInterrupt ("interrupted", 130), or aborted with a stack dump
    pytest.param("ray::_run_chunk", "pid", signal.SIGTERM, 143, "csql-sim: terminated", id="sigterm-while-tasks-run"),
    # Ray's own handler, in force during ray.init, exited with status 15 and said nothing
    pytest.param("gcs_server", "pid", signal.SIGTERM, 143, "csql-sim: terminated", id="sigterm-while-ray-starts"),
    # a terminal's Ctrl-C reaches the process group; the process crashed (SIGSEGV) after its line
    pytest.param("ray::_run_chunk", "group", signal.SIGINT, 130, "csql-sim: interrupted", id="ctrl-c-while-tasks-run"),
]


@linux
@needs_ray
@pytest.mark.slow
@pytest.mark.parametrize("running, to, sig, status, line", SIGNALS)
def test_a_signal_is_one_line_and_leaves_no_ray_process(started, running, to, sig, status, line):
    proc = _start_evaluate(started, running)
    if to == "group":
        os.killpg(proc.pid, sig)
    else:
        proc.send_signal(sig)
    out, err = proc.communicate(timeout=HANG_GUARD)
    assert (proc.returncode, err.strip(), out) == (status, line, ""), err
    wait_for(lambda: not session(proc.pid), GONE_GUARD, f"left running: {session(proc.pid)}")
