"""Where independent tasks run: a local process pool (the default) or Ray.

:func:`map_tasks` calls ``fn(item)`` for every item and returns the results in item
order, whichever backend runs them, so a seeded run gives the same results on both.
Items are sent in chunks; a progress bar counts finished items. A task that fails as a
task can (:data:`TASK_ERRORS`: the project's :class:`CsqlError`, e.g. a world that cannot
be built, or running out of memory), or whose worker dies (the pool breaks, Ray loses the
worker or its node), yields a :class:`TaskFailure` in its place instead of stopping the
run. Any other exception is a bug in the task and propagates out of :func:`map_tasks`
(the remaining tasks are cancelled). Ctrl-C cancels what is still running and re-raises
:class:`KeyboardInterrupt`; in a Ray session that
:func:`csql_sim.infra.ray_session.ray_session` opened, its shutdown ends them (a
``ray.cancel`` racing a finishing task can abort the process in Ray's core).

With Ray (the optional extra ``pip install "csql-sim[ray]"``), the chunks are Ray tasks:
on a local instance started for the call (``address=None``, ``workers`` CPUs) or on an
existing cluster (``address="auto"`` on a cluster node, or ``"ray://head:10001"``).
Every node needs the same csql-sim and Python versions. A Ray session that this module
started is shut down before :func:`map_tasks` returns; one the caller started with
``ray.init`` is used and left running. A local instance's processes end with this
process even if it is killed (:func:`csql_sim.infra.workers.reaper`); an address that
does not answer fails within seconds, in one line (:mod:`csql_sim.infra.ray_address`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from functools import cache
from typing import Any, TypeVar

from tqdm import tqdm

from csql_sim.infra.errors import CsqlError
from csql_sim.infra.ray_session import SHUTDOWN_ENDS_TASKS, ray_session
from csql_sim.infra.workers import worker_count, worker_pool

BACKENDS = ("processes", "ray")
TASK_ERRORS = (CsqlError, MemoryError)  # how a task (or a worker's setup) may fail without a bug
T = TypeVar("T")
R = TypeVar("R")


@dataclass(frozen=True)
class Backend:
    """Where tasks run.

    Attributes:
        kind: ``"processes"`` (a local process pool) or ``"ray"``.
        workers: processes of the pool, or CPUs of a local Ray instance (default: every
            core; 1 runs the pool's tasks in this process). Ignored on a Ray cluster.
        address: a running Ray cluster (``"auto"``, ``"ray://host:10001"``); None starts a
            local instance. Only for ``kind="ray"``.
    """

    kind: str = "processes"
    workers: int | None = None
    address: str | None = None

    def __post_init__(self) -> None:
        if self.kind not in BACKENDS:
            raise CsqlError(f"backend must be one of {', '.join(BACKENDS)}, got {self.kind!r}")
        if self.workers is not None and self.workers < 1:
            raise CsqlError(f"--workers must be a positive integer, got {self.workers}")
        if self.address is not None and self.kind != "ray":
            raise CsqlError("--address needs --backend ray")


@dataclass(frozen=True)
class TaskFailure:
    """Stands in for the result of a task that raised one of :data:`TASK_ERRORS` or whose worker died."""

    reason: str


Setup = Callable[..., None]
_SETUP_DONE: dict[tuple[str, str], tuple] = {}  # owned by _run_chunk: each setup's last arguments in this process


def _run_chunk(fn: Callable[[T], R], chunk: Sequence[T], setup: Setup | None,
               setup_args: tuple) -> list[R | TaskFailure]:
    """Run ``fn`` on each item of ``chunk`` in a worker; one of :data:`TASK_ERRORS` becomes a TaskFailure.

    Any other exception (a bug: a TypeError, an AttributeError ...) propagates.

    ``setup(*setup_args)`` runs first unless this process's last run of ``setup`` had equal
    arguments: a process serves many calls (Ray reuses workers; with one worker the tasks
    run in the caller's process), and a setup with other arguments in between replaced
    the state the setup leaves.
    """
    if setup is not None:
        key = (setup.__module__, setup.__qualname__)
        if key not in _SETUP_DONE or _SETUP_DONE[key] != setup_args:
            _SETUP_DONE.pop(key, None)  # half done until it returns
            try:
                setup(*setup_args)
            except TASK_ERRORS as exc:  # every task of the chunk fails with the setup's reason
                return [TaskFailure(f"worker setup failed: {_describe(exc)}")] * len(chunk)
            _SETUP_DONE[key] = setup_args
    out: list[R | TaskFailure] = []
    for item in chunk:
        try:
            out.append(fn(item))
        except TASK_ERRORS as exc:  # reported in the task's place, like a failed episode
            out.append(TaskFailure(_describe(exc)))
    return out


def _describe(exc: BaseException) -> str:
    """``Type: message`` on one line."""
    return f"{type(exc).__name__}: {' '.join(str(exc).split())}"


def map_tasks(fn: Callable[[T], R], items: Sequence[T], backend: Backend = Backend(), *,
              setup: Setup | None = None, setup_args: tuple = (), progress: bool = False,
              desc: str = "tasks", unit: str = "task",
              on_result: Callable[[int, R | TaskFailure], None] | None = None) -> list[R | TaskFailure]:
    """``[fn(item) for item in items]`` on ``backend``, in item order.

    Args:
        fn: a module-level function (it is pickled by reference).
        items: the tasks' arguments (picklable).
        backend: where to run them.
        setup: a module-level function run once in each worker before its first task
            (e.g. building a policy), and again when its arguments differ from those of
            its last run in that worker; ``setup_args`` are compared with ``==``.
        setup_args: the arguments of ``setup``; on Ray they go to the object store once.
        progress: show a tqdm bar on stderr (and, for Ray, one line on where it runs).
        desc: the bar's label.
        unit: the bar's unit.
        on_result: called in this process with (item index, result) as each task's chunk
            comes back, in completion order (e.g. to save each result before the run ends);
            what it returns takes the result's place in the list returned (a summary lets a
            large result go as soon as it is saved).

    Returns:
        One result, or a :class:`TaskFailure`, per item.

    Raises:
        Exception: any exception of a task (or setup) other than :data:`TASK_ERRORS`: a bug.
    """
    items = list(items)
    if not items:
        return []
    if backend.kind == "ray":
        with ray_session(backend.address, backend.workers, announce=progress) as cpus, \
                tqdm(total=len(items), desc=desc, unit=unit, disable=not progress) as bar:
            return _map_ray(fn, items, cpus, setup, setup_args, _Sink(bar, on_result))
    with tqdm(total=len(items), desc=desc, unit=unit, disable=not progress) as bar:
        return _map_processes(fn, items, backend.workers, setup, setup_args, _Sink(bar, on_result))


@dataclass(frozen=True)
class _Sink:
    """Where a finished chunk's results go: the bar, and ``on_result`` for each."""

    bar: tqdm
    on_result: Callable[[int, Any], None] | None

    def put(self, first: int, results: list) -> list:
        """Hand a chunk's results on; what to keep of them."""
        if self.on_result is not None:
            results = [self.on_result(first + k, r) for k, r in enumerate(results)]
        self.bar.update(len(results))
        return results


def _starts(chunks: list[list]) -> list[int]:
    """The index of each chunk's first item."""
    out, at = [], 0
    for c in chunks:
        out.append(at)
        at += len(c)
    return out


def _chunks(items: list[T], slots: int) -> list[list[T]]:
    """About 16 chunks per slot (as ProcessPoolExecutor.map's usual chunksize advice)."""
    size = max(1, len(items) // (slots * 16))
    return [items[i:i + size] for i in range(0, len(items), size)]


def _map_processes(fn: Callable, items: list, workers: int | None, setup: Setup | None, setup_args: tuple,
                   sink: _Sink) -> list:
    """The pool's side of :func:`map_tasks` (:func:`csql_sim.infra.workers.worker_pool`: workers die with us)."""
    workers = worker_count(workers, len(items))
    if workers <= 1:
        out: list = []
        for item in items:
            out.extend(sink.put(len(out), _run_chunk(fn, [item], setup, setup_args)))
        return out
    chunks = _chunks(items, workers)
    starts = _starts(chunks)
    results: list[list | None] = [None] * len(chunks)
    with worker_pool(workers) as pool:
        futures = {pool.submit(_run_chunk, fn, c, setup, setup_args): k for k, c in enumerate(chunks)}
        pending = set(futures)
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                k = futures[future]
                try:
                    results[k] = future.result()
                except BrokenProcessPool as exc:
                    results[k] = [TaskFailure(f"worker process died: {exc}")] * len(chunks[k])
                results[k] = sink.put(starts[k], results[k])
                del futures[future]
    return [r for chunk in results for r in chunk]  # type: ignore[union-attr]


@cache
def _remote_run_chunk() -> Any:
    import ray

    return ray.remote(max_retries=1)(_run_chunk)


def _map_ray(fn: Callable, items: list, cpus: int, setup: Setup | None, setup_args: tuple, sink: _Sink) -> list:
    """Ray's side of :func:`map_tasks`, inside a Ray session with ``cpus`` CPUs.

    ``setup_args`` are put in the object store once; every chunk's task gets the reference
    (Ray resolves a reference passed as an argument before the task runs).
    """
    import ray
    from ray.exceptions import RayError, RayTaskError

    chunks = _chunks(items, cpus)
    starts = _starts(chunks)
    remote = _remote_run_chunk()
    shared = ray.put(setup_args)
    index = {remote.remote(fn, c, setup, shared): k for k, c in enumerate(chunks)}  # dropped when done
    results: list[list | None] = [None] * len(chunks)
    pending = list(index)
    try:
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            for ref in done:
                k = index.pop(ref)
                try:
                    results[k] = ray.get(ref)
                except RayTaskError:
                    raise  # the task itself raised (its TASK_ERRORS came back as failures): a bug
                except RayError as exc:  # the worker or its node died, the object was lost, ...
                    reason = " ".join(str(exc).split())[:200]
                    results[k] = [TaskFailure(f"ray task failed: {reason}")] * len(chunks[k])
                results[k] = sink.put(starts[k], results[k])
    except BaseException:
        if not SHUTDOWN_ENDS_TASKS.get():  # else not cancelled: ray.cancel races a reply and aborts the process
            for ref in pending:
                ray.cancel(ref, force=True)
        raise
    return [r for chunk in results for r in chunk]  # type: ignore[union-attr]
