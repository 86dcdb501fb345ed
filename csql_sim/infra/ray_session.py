"""A Ray session for csql-sim's tasks: opened, shut down, and quiet and prompt on Ctrl-C and SIGTERM.

:func:`ray_session` connects to a running cluster or starts a local instance, and shuts
down what it opened. Ray, left to itself, ends a SIGTERM'd driver by ``sys.exit(15)``
(no line) or by its C++ failure-signal handler's stack dump; a cancel racing a finishing
task aborts the process (Ray 2.60). Those are handled here; that Ray reports a handler's
exception as a KeyboardInterrupt, and that its threads crash in the interpreter's
finalization, in :mod:`csql_sim.cli` (``docs/reliability.md``, "Signals with Ray").
"""

from __future__ import annotations

import logging
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import ExitStack, contextmanager, nullcontext
from contextvars import ContextVar
from typing import Any

from csql_sim.infra.errors import CsqlError, Terminated
from csql_sim.infra.ray_address import check_ray_address
from csql_sim.infra.workers import reaper, worker_count

NO_FAILURE_HANDLER = "RAY_DISABLE_FAILURE_SIGNAL_HANDLER"  # read once, when Ray is imported
# True inside a ray_session that opened Ray: its shutdown ends the tasks still running
SHUTDOWN_ENDS_TASKS: ContextVar[bool] = ContextVar("csql_sim_ray_shutdown_ends_tasks", default=False)


@contextmanager
def ray_session(address: str | None, workers: int | None, announce: bool) -> Iterator[int]:
    """Connect to the cluster at ``address`` (None: start a local instance of ``workers`` CPUs); yields the CPUs.

    Shuts Ray down on exit if this call started it; a session the caller opened stays.
    A local instance runs under :func:`csql_sim.infra.workers.reaper`: its processes
    end with this one, even after a SIGKILL. SIGTERM keeps the handler it had before
    ``ray.init``, and :func:`csql_sim.infra.backends.map_tasks` leaves its remaining
    tasks to the shutdown (:data:`SHUTDOWN_ENDS_TASKS`).
    """
    ray = _import_ray()
    if ray.is_initialized():
        yield _announce(ray, "existing session", time.perf_counter(), announce)
        return
    with ExitStack() as stack:
        if address is None:
            stack.enter_context(reaper())
        else:
            check_ray_address(address)
        began = time.perf_counter()
        stack.push(_shutdown(ray))  # also after a ray.init that a signal cut short
        _init_ray(ray, address, workers)
        stack.callback(SHUTDOWN_ENDS_TASKS.reset, SHUTDOWN_ENDS_TASKS.set(True))
        yield _announce(ray, f"cluster at {address}" if address else "local instance", began, announce)


def _import_ray() -> Any:
    """``import ray``, the first time without its C++ failure-signal handler in this process.

    The handler prints a stack dump for SIGTERM too. The variable is set only for the
    import (unless the caller set it), so Ray's own processes keep their crash reports.
    """
    set_here = NO_FAILURE_HANDLER not in os.environ and "ray" not in sys.modules
    if set_here:
        os.environ[NO_FAILURE_HANDLER] = "1"
    try:
        import ray
    except ImportError:
        raise CsqlError('--backend ray needs Ray: pip install "csql-sim[ray]"') from None
    finally:
        if set_here:
            del os.environ[NO_FAILURE_HANDLER]
    return ray


def _init_ray(ray: Any, address: str | None, workers: int | None) -> None:
    """``ray.init``, quiet; a local instance gets at most the cores.

    ``ray.init`` replaces SIGTERM's handler with one that ends the process by
    ``sys.exit(15)``, without a word: that becomes :class:`Terminated`, and the handler
    from before is back when this returns (in the main thread; ignored after a SIGTERM).
    """
    kwargs: dict[str, Any] = {"include_dashboard": False, "logging_level": logging.ERROR, "log_to_driver": False}
    if address is None:
        kwargs["num_cpus"] = worker_count(workers, os.cpu_count() or 1)
    os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.getsignal(signal.SIGTERM) if main_thread else None
    try:
        ray.init(address=address, **kwargs)
    except SystemExit as exc:
        if exc.code != signal.SIGTERM:
            raise
        previous = signal.SIG_IGN  # a second SIGTERM cannot cut the unwinding short
        raise Terminated from None
    except (ConnectionError, RuntimeError, ValueError) as exc:
        raise CsqlError(f"cannot start Ray at {address or 'a local instance'}: {' '.join(str(exc).split())}") from None
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, signal.SIG_DFL if previous is None else previous)


def _shutdown(ray: Any) -> Callable[..., bool]:
    """An exit callback: ``ray.shutdown()``, with file descriptor 2 on /dev/null when unwinding from an interrupt.

    Tasks still running when an interrupted session shuts down fail, and Ray's C++ core
    may log that on stderr (``Failed to push error to driver``) beside the command's one line.
    """
    def exit_(exc_type: type[BaseException] | None, *_: object) -> bool:
        interrupted = exc_type is not None and issubclass(exc_type, KeyboardInterrupt)
        with _stderr_to_null() if interrupted else nullcontext():
            ray.shutdown()
        return False

    return exit_


@contextmanager
def _stderr_to_null() -> Iterator[None]:
    """File descriptor 2 on /dev/null inside the block; left as it is if that cannot be done."""
    try:
        if sys.stderr is not None:
            sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):
        yield
        return
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 2)
        os.close(null)
    except OSError:
        pass
    try:
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def _announce(ray: Any, where: str, began: float, announce: bool) -> int:
    """The CPUs of the session; with ``announce``, one line on stderr saying where tasks run."""
    cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
    if announce:
        print(f"ray: {where}, {cpus} CPUs (ready in {time.perf_counter() - began:.1f} s)", file=sys.stderr)
    return cpus
