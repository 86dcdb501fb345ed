"""Worker processes that die with their parent and stop at once on Ctrl-C.

:func:`worker_pool` is the one way the tool starts processes (experiment cycles, evaluation
episodes, video frames). Its workers

* ignore SIGINT, from their start (they start with it blocked): a Ctrl-C reaches the main
  process only, which then terminates them (the pool's own shutdown would wait for every
  queued task);
* exit when the main process dies, even by SIGKILL: on Linux the kernel sends them
  SIGKILL (``prctl(PR_SET_PDEATHSIG)``) when they are its children; in every case a
  watchdog thread waits on the main process's pid (a pidfd, or polling twice a second);
* are never forked from a process that runs other threads (a Ray session, a progress
  bar's monitor): they are spawned instead (:func:`pool_context`).

:func:`worker_count` caps the number of processes at the number of cores and of tasks.

Processes that others start for us (a local Ray instance's daemons and agents) cannot be
given a death signal: :func:`reaper` starts a small watchdog process that records every
process started below this one inside its block and, once this process is gone (even by
SIGKILL) or the block ends, terminates those still running (Linux; elsewhere a no-op).
"""

from __future__ import annotations

import ctypes
import multiprocessing
import os
import select
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ProcessPoolExecutor
from contextlib import contextmanager
from multiprocessing.context import BaseContext

PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
WATCHDOG_SECONDS = 0.5
STOP_SECONDS = 1.0  # how long a terminated worker may take before it is killed
REAPER_POLL_SECONDS = 0.25  # how often the reaper records the processes below its parent


def worker_count(requested: int | None, tasks: int) -> int:
    """Processes to start: ``requested`` (default: every core), at most the cores and ``tasks``, at least 1.

    More processes than cores would only share them, each with its own copy of the
    task's state: ``--workers 1000`` must not start a thousand processes.
    """
    cores = os.cpu_count() or 1
    return max(1, min(requested or cores, cores, tasks))


def _gone(parent: int) -> bool:
    """Whether process ``parent`` no longer exists (``os.kill(pid, 0)``: signals nothing)."""
    try:
        os.kill(parent, 0)
    except ProcessLookupError:
        return True
    except PermissionError:  # it exists, as another user's process
        return False
    return False


def _watch_parent(parent: int, pidfd: int | None, ppid: int) -> None:
    """Exit this process once ``parent`` is gone: wait on its pidfd, or poll every half second.

    Polling also ends the process once it is orphaned (its own parent, ``ppid`` at its start,
    changed): a parent that died but is not reaped yet is a zombie, which ``os.kill`` still finds.
    """
    if pidfd is not None:
        select.select([pidfd], [], [])  # readable once the process has exited
        os._exit(1)
    while os.getppid() == ppid and not _gone(parent):
        time.sleep(WATCHDOG_SECONDS)
    os._exit(1)


def _open_pidfd(parent: int) -> int | None:
    """A pidfd of process ``parent`` (Linux 5.3+; else None); exit now if it is already gone."""
    try:
        return os.pidfd_open(parent)
    except ProcessLookupError:
        os._exit(1)
    except (AttributeError, OSError):  # no pidfd_open in this Python or kernel
        return None


def die_with_parent(parent: int) -> None:
    """In a worker: ignore SIGINT and exit as soon as process ``parent`` is gone.

    ``parent`` is the process that started the pool, the worker's parent when it was forked
    or spawned from it, not when a forkserver started it: the kernel's death signal
    (``PR_SET_PDEATHSIG``) comes when the worker's own parent dies, so it is asked for
    only when that parent is ``parent``. A watchdog thread waits for ``parent`` by pid in
    every case.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    ppid = os.getppid()
    if ppid == parent and sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
        except (OSError, AttributeError):
            pass
        if os.getppid() != parent:  # the parent died before the line above
            os._exit(1)
    pidfd = _open_pidfd(parent)
    threading.Thread(target=_watch_parent, args=(parent, pidfd, ppid), name="csql-sim-watchdog",
                     daemon=True).start()


def _initialize(parent: int, initializer: Callable[..., object] | None, initargs: tuple) -> None:
    die_with_parent(parent)
    if initializer is not None:
        initializer(*initargs)


def other_threads_alive() -> bool:
    """Whether this process runs threads besides the main one (Python's, or a Ray session's own)."""
    if threading.active_count() > 1:
        return True
    ray = sys.modules.get("ray")
    is_initialized = getattr(ray, "is_initialized", None)
    return bool(is_initialized is not None and is_initialized())


def pool_context(mp_context: BaseContext | None = None) -> BaseContext:
    """How a pool's workers start: ``mp_context`` if given, else the default, but never by fork with threads alive.

    A fork copies a lock held by another thread, held for ever in the child: a worker
    forked beside a Ray session's threads (or any thread) may hang. Such a process
    spawns its workers instead (a fresh interpreter: the same results, tasks carry their seeds).
    """
    if mp_context is not None:
        return mp_context
    method = multiprocessing.get_start_method(allow_none=True) or multiprocessing.get_all_start_methods()[0]
    if method == "fork" and other_threads_alive():
        method = "spawn"
    return multiprocessing.get_context(method)


def stop_pool(pool: ProcessPoolExecutor) -> None:
    """Cancel queued tasks and end every worker now (SIGTERM, then SIGKILL after a second)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    results = getattr(pool, "_result_queue", None)  # shutdown() drops it
    manager = getattr(pool, "_executor_manager_thread", None)  # and this
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
    _end_result_pipe(results)
    if manager is not None and manager is not threading.current_thread():
        # Let the manager thread close its wake-up pipe now: at exit the interpreter wakes every
        # pool's manager, and a close racing that wake-up printed "Bad file descriptor" (CPython 3.11).
        manager.join(STOP_SECONDS)


def _end_result_pipe(results: object) -> None:
    """Close this process's writing end of a pool's result pipe (``results``), once its workers are gone.

    A worker killed while sending a result (a chunk of video frames is megabytes) leaves half
    a message in the pipe: the pool's manager thread read the start and waited for the rest
    for ever, and so did the interpreter, which joins that thread at exit. With no writer
    left, the read fails (EOF): the manager thread marks the pool broken and ends.
    """
    writer = getattr(results, "_writer", None)
    if writer is not None:
        try:
            writer.close()
        except OSError:
            pass


@contextmanager
def _sigint_blocked() -> Iterator[None]:
    """Block SIGINT in this thread: a Ctrl-C meanwhile stays pending and is delivered at the end."""
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


class _WorkerPool(ProcessPoolExecutor):
    """A pool whose workers start with SIGINT blocked (they inherit the mask of the thread that submits).

    A spawned worker imports for seconds before :func:`die_with_parent` ignores SIGINT: a
    Ctrl-C then printed a KeyboardInterrupt traceback from the worker. Workers start only in
    ``submit`` (``map`` calls it); the parent gets a Ctrl-C sent meanwhile once it returns.
    """

    def submit(self, fn: Callable[..., object], /, *args: object, **kwargs: object) -> Future:  # noqa: D102
        with _sigint_blocked():
            return super().submit(fn, *args, **kwargs)


@contextmanager
def worker_pool(workers: int, initializer: Callable[..., object] | None = None,
                initargs: tuple = (), mp_context: BaseContext | None = None) -> Iterator[ProcessPoolExecutor]:
    """A process pool whose workers die with this process and stop at once on an exception.

    On normal exit the pool is shut down waiting for its tasks; on any exception, a
    KeyboardInterrupt included, queued tasks are cancelled and the workers terminated.
    ``mp_context`` chooses how workers start (default: :func:`pool_context`, the platform's
    unless other threads run; the EGL renderer needs ``spawn``).
    """
    pool = _WorkerPool(max_workers=workers, initializer=_initialize,
                       initargs=(os.getpid(), initializer, initargs), mp_context=pool_context(mp_context))
    try:
        yield pool
    except BaseException:
        stop_pool(pool)
        raise
    pool.shutdown(wait=True)


def python_command(code: str, *args: str) -> tuple[list[str], dict[str, str]]:
    """The command line and environment of a child ``python -c code args`` that can import this package."""
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [root, os.environ.get("PYTHONPATH")]))}
    return [sys.executable, "-c", code, *args], env


def _process_table() -> dict[int, tuple[int, int]]:
    """``pid -> (parent pid, start time)`` of every process, from /proc (Linux)."""
    table = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat", "rb") as fh:
                    fields = fh.read().rsplit(b")", 1)[1].split()
            except (OSError, IndexError):
                continue
            table[int(entry)] = (int(fields[1]), int(fields[19]))
    return table


def _descendants(roots: list[int], table: dict[int, tuple[int, int]]) -> dict[int, int]:
    """``pid -> start time`` of every process below ``roots`` in ``table``."""
    children: dict[int, list[int]] = {}
    for pid, (parent, _) in table.items():
        children.setdefault(parent, []).append(pid)
    found: dict[int, int] = {}
    stack = list(roots)
    while stack:
        for child in children.get(stack.pop(), ()):
            if child not in found:
                found[child] = table[child][1]
                stack.append(child)
    return found


def _end_processes(recorded: dict[int, int]) -> None:
    """SIGTERM the ``recorded`` processes still running (same pid and start time), SIGKILL them a second later."""
    def running() -> list[int]:
        table = _process_table()
        return [pid for pid, start in recorded.items() if table.get(pid, (0, -1))[1] == start]

    for sig in (signal.SIGTERM, signal.SIGKILL):
        for pid in running():
            try:
                os.kill(pid, sig)
            except OSError:  # gone meanwhile, or not ours to signal
                pass
        deadline = time.monotonic() + STOP_SECONDS
        while running() and time.monotonic() < deadline:
            time.sleep(0.05)


def reap(parent: int, fd: int = 0) -> None:
    """The reaper process: record what ``parent`` starts; when it is gone or closes ``fd``, end it all.

    Processes below ``parent`` when the reaper starts are left alone; it says ``ready``
    on stdout once it has seen them. It ignores SIGINT and SIGTERM (a Ctrl-C in a terminal
    reaches the whole process group): it ends on its own once its work is done.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    me = os.getpid()
    before = set(_descendants([parent], _process_table())) | {me}
    print("ready", flush=True)
    recorded: dict[int, int] = {}
    while os.getppid() == parent:
        recorded.update({pid: start for pid, start in _descendants([parent], _process_table()).items()
                         if pid not in before})
        ready, _, _ = select.select([fd], [], [], REAPER_POLL_SECONDS)
        if ready and not os.read(fd, 4096):  # EOF: the parent closed the pipe, or died
            break
    recorded.update(_descendants(list(recorded), _process_table()))  # what they started since (workers)
    recorded.pop(me, None)
    _end_processes(recorded)


@contextmanager
def reaper() -> Iterator[None]:
    """Every process started below this one inside the block ends with it, even after a SIGKILL.

    For processes that a library starts and that do not die with their parent (a local
    Ray instance's agents outlive it by a minute): a watchdog process (:func:`reap`)
    records them and terminates those still running when this process dies or the block
    ends. Linux only (it reads /proc); elsewhere the block runs without one.
    """
    if not sys.platform.startswith("linux"):
        yield
        return
    argv, env = python_command("import sys; from csql_sim.infra.workers import reap; reap(int(sys.argv[1]))",
                               str(os.getpid()))
    watchdog = subprocess.Popen(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                env=env)
    try:
        watchdog.stdout.readline()  # "ready" (or EOF if it could not start: then there is none)
        yield
    finally:
        watchdog.stdin.close()
        try:
            watchdog.wait(3 * STOP_SECONDS)
        except subprocess.TimeoutExpired:  # it ends on its own
            pass
        watchdog.stdout.close()
