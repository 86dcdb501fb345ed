import os
import signal

import pytest

from csql_sim.core.state.notation import parse_config


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_auto_num_workers(config):
    """``-n auto`` (pyproject.toml's addopts): one worker per core this process may run on.

    pytest-xdist would count the machine's physical cores, which a container or a CPU
    affinity mask may not grant; ``PYTEST_XDIST_AUTO_NUM_WORKERS`` still decides where set.
    """
    if os.environ.get("PYTEST_XDIST_AUTO_NUM_WORKERS"):
        return None
    usable = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else range(os.cpu_count() or 1)
    return max(1, len(usable))


@pytest.fixture
def task():
    """The paper's test task: A on B on C to C on A on B (8 actions)."""
    return parse_config("CBA"), parse_config("BAC")


@pytest.fixture(scope="session", autouse=True)
def sigint_for_children():
    """Children start with SIGINT at its default, even when the suite itself runs with it ignored.

    A shell starts a background job (``pytest &``) with SIGINT ignored, and a child inherits
    that: the tests that stop a command with Ctrl-C would then wait in vain (csql-sim keeps
    an ignored SIGINT, as Unix tools do). A handler set here is reset to the default in
    every child that execs, so the tests rely on no disposition of the shell's.
    """
    previous = signal.getsignal(signal.SIGINT)
    if previous == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    if previous == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
