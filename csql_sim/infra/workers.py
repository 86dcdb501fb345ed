"""Worker processes that die with their parent and stop at once on Ctrl-C.

:func:`worker_pool` is the one way the tool starts processes (experiment cycles, evaluation
episodes, video frames). Its workers

* ignore SIGINT: a Ctrl-C reaches the main process only, which then terminates them (the
  pool's own shutdown would wait for every queued task);
* exit when the main process dies, even by SIGKILL: on Linux the kernel sends them
  SIGKILL (``prctl(PR_SET_PDEATHSIG)``); elsewhere, and as a fallback, a watchdog thread
  polls the parent's pid twice a second.

:func:`worker_count` caps the number of processes at the number of tasks.
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager
from multiprocessing.context import BaseContext

PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
WATCHDOG_SECONDS = 0.5
STOP_SECONDS = 1.0  # how long a terminated worker may take before it is killed


def worker_count(requested: int | None, tasks: int) -> int:
    """Processes to start: ``requested`` (default: every core), at most ``tasks``, at least 1."""
    return max(1, min(requested or os.cpu_count() or 1, tasks))


def _watch_parent(parent: int) -> None:
    while True:
        time.sleep(WATCHDOG_SECONDS)
        if os.getppid() != parent:
            os._exit(1)


def die_with_parent(parent: int) -> None:
    """In a worker: ignore SIGINT and exit as soon as process ``parent`` is gone."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:  # the parent died before the line above
        os._exit(1)
    threading.Thread(target=_watch_parent, args=(parent,), name="csql-sim-watchdog", daemon=True).start()


def _initialize(parent: int, initializer: Callable[..., object] | None, initargs: tuple) -> None:
    die_with_parent(parent)
    if initializer is not None:
        initializer(*initargs)


def stop_pool(pool: ProcessPoolExecutor) -> None:
    """Cancel queued tasks and end every worker now (SIGTERM, then SIGKILL after a second)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    deadline = time.monotonic() + STOP_SECONDS
    for process in processes:
        process.join(max(0.0, deadline - time.monotonic()))
        if process.is_alive():
            process.kill()
            process.join(STOP_SECONDS)


@contextmanager
def worker_pool(workers: int, initializer: Callable[..., object] | None = None,
                initargs: tuple = (), mp_context: BaseContext | None = None) -> Iterator[ProcessPoolExecutor]:
    """A process pool whose workers die with this process and stop at once on an exception.

    On normal exit the pool is shut down waiting for its tasks; on any exception, a
    KeyboardInterrupt included, queued tasks are cancelled and the workers terminated.
    ``mp_context`` chooses how workers start (default: the platform's; the EGL renderer
    needs ``spawn``).
    """
    pool = ProcessPoolExecutor(max_workers=workers, initializer=_initialize,
                               initargs=(os.getpid(), initializer, initargs), mp_context=mp_context)
    try:
        yield pool
    except BaseException:
        stop_pool(pool)
        raise
    pool.shutdown(wait=True)
