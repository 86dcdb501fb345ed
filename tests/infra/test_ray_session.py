"""A session map_tasks opens for a library caller leaves the caller's process as it found it."""

import math
import os
import signal

import pytest

from csql_sim.infra.backends import Backend, map_tasks
from csql_sim.infra.ray_session import NO_FAILURE_HANDLER


def _callers_handler(signum, frame):
    raise AssertionError("not called in this test")


@pytest.mark.slow
def test_the_callers_sigterm_handler_and_environment_are_restored(monkeypatch):
    ray = pytest.importorskip("ray", reason="the ray extra is not installed")
    if ray.is_initialized():
        pytest.skip("a Ray session is already open in this process; this test opens its own")
    monkeypatch.delenv(NO_FAILURE_HANDLER, raising=False)
    previous = signal.signal(signal.SIGTERM, _callers_handler)
    try:
        assert map_tasks(math.sqrt, [1.0, 4.0], Backend("ray", workers=2)) == [1.0, 2.0]
        assert signal.getsignal(signal.SIGTERM) is _callers_handler
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert not ray.is_initialized() and NO_FAILURE_HANDLER not in os.environ
