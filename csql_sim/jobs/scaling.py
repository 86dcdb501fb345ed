"""The scaling study: trials until the greedy plans are optimal for every pair, per n and method.

Each (n, method) trains one agent from the seed with the random tasks alone (no planning
sweep: this measures learning from trials), with the temperature reaching its floor after
60% of ``max_trials``, and checks after every 1% of ``max_trials`` whether the greedy
action of every (state, goal) pair lies on an optimal plan. That local test is exact: a
plan is optimal iff every step lowers the BFS distance to the goal by one. The cell is
empty when ``max_trials`` is reached first.

Each cell also reports its peak memory: the peak resident set size (RSS) of the process
running it, while it ran. On Linux the kernel's high-water mark (``VmHWM``) is reset
before the cell (``/proc/self/clear_refs``) and read after it; where that cannot be done,
it is ``resource.getrusage``'s ``ru_maxrss``, the process's peak since it started (an
upper bound). Either includes the interpreter and its libraries (some 150 MB).
"""

from __future__ import annotations

import csv
import io
import os
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from csql_sim.core.search import count_optimal_greedy
from csql_sim.infra.backends import Backend, TaskFailure, map_tasks
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import write_or_keep
from csql_sim.learners.learner import Learner
from csql_sim.learners.params import default_params
from csql_sim.learners.training import make_learner

if TYPE_CHECKING:
    from matplotlib.figure import Figure

COLUMNS = ("method", "blocks", "trials_to_all_optimal", "steps", "wall_seconds", "peak_rss_mb",
           "population")
CHECKS = 100


@dataclass(frozen=True)
class ScalingRow:
    """One (method, n) cell; ``trials`` is None when the cap was reached first.

    ``peak_rss_mb``: the peak resident set size while the cell ran, in MB (10**6 bytes;
    see the module's docstring); 0 where it could not be measured. ``population``: the
    Q-classifiers (table rows' entries for LT-QL) the learner holds at the end (for
    ``xcs-ql``, its generalized population).
    """

    method: str
    blocks: int
    trials: int | None
    steps: int
    wall_seconds: float
    optimal_pairs: int
    pairs: int
    peak_rss_mb: float = 0.0
    population: int = 0


def optimal_pairs(learner: Learner) -> int:
    """How many ordered pairs the learner's greedy policy (:meth:`Learner.greedy_table`) plans optimally."""
    return count_optimal_greedy(learner.greedy_table().best, learner.n)


class _Reached(Exception):
    """Raised from the trial callback when every pair is optimal."""


def reset_peak_rss() -> bool:
    """Reset this process's peak resident set size (Linux's ``VmHWM``); whether that was possible."""
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
    except OSError:
        return False
    return True


def peak_rss_bytes(since_reset: bool = True) -> int:
    """This process's peak resident set size in bytes: ``VmHWM`` (since :func:`reset_peak_rss`) or ``ru_maxrss``."""
    if since_reset:
        try:
            with open("/proc/self/status") as fh:
                for line in fh:
                    if line.startswith("VmHWM:"):
                        return int(line.split()[1]) * 1024
        except (OSError, ValueError, IndexError):
            pass
    try:
        import resource
    except ImportError:  # no getrusage (Windows)
        return 0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak if sys.platform == "darwin" else peak * 1024  # bytes on macOS, kB elsewhere


def run_cell(method: str, n: int, seed: int, max_trials: int, engine: str | None = None) -> ScalingRow:
    """Train one agent until all pairs are optimal or ``max_trials``; its row.

    ``engine``: as :func:`~csql_sim.learners.training.make_learner`'s (None: the array
    engine where the method has one); trials and steps do not depend on it.
    """
    base = default_params(method)
    overrides: dict = {"t_decay": (base.t_min / base.t0) ** (1.0 / (0.6 * max_trials))}
    if method in ("cs-ql", "xcs-ql"):
        overrides["sweep"] = False
    reset = reset_peak_rss()
    learner = make_learner(method, n, overrides, seed=seed, engine=engine)
    count = len(learner.world.states)
    every = max(1, max_trials // CHECKS)
    found: list[int] = []
    spent = [0.0]

    def check(k: int) -> None:
        if (k + 1) % every == 0:
            t0 = time.perf_counter()
            good = optimal_pairs(learner)
            spent[0] += time.perf_counter() - t0
            found[:] = [k + 1, good]
            if good == count * (count - 1):
                raise _Reached

    began = time.perf_counter()
    reached = True
    try:
        learner.train(max_trials, on_trial=check)
        reached = False
    except _Reached:
        pass
    wall = time.perf_counter() - began - spent[0]
    trials, good = (found or [max_trials, optimal_pairs(learner)])[:2]
    peak = peak_rss_bytes(reset) / 1e6
    population = len(getattr(learner, "population", ())) or learner.counts()[1]
    return ScalingRow(method, n, trials if reached else None, learner.t, wall, good, count * (count - 1), peak,
                      population)


@dataclass(frozen=True)
class CellJob:
    """One (method, n) cell to run."""

    method: str
    n: int
    seed: int
    max_trials: int


def _warm_up(methods: tuple[str, ...]) -> None:
    """Worker setup: load the methods' engines (compiling the array engines' kernels) before any cell is timed."""
    for method in methods:
        make_learner(method, 2, engine=None).train(1)


def _run_job(job: CellJob) -> ScalingRow:
    return run_cell(job.method, job.n, job.seed, job.max_trials)


def run_scaling(blocks: Sequence[int], methods: Sequence[str], seed: int = 0, max_trials: int = 20_000,
                progress: bool = False, backend: Backend | None = None) -> list[ScalingRow]:
    """Every (n, method) cell in order.

    ``backend`` (default: one cell after another in this process, so that no two cells
    share the cores while they are timed) may run cells in parallel, on Ray too; trials
    and steps do not depend on it, wall seconds do.
    """
    jobs = [CellJob(m, n, seed, max_trials) for n in blocks for m in methods]
    rows = map_tasks(_run_job, jobs, backend or Backend(workers=1), setup=_warm_up,
                     setup_args=(tuple(dict.fromkeys(methods)),), progress=progress, desc="scaling", unit="cell")
    for job, row in zip(jobs, rows, strict=True):
        if isinstance(row, TaskFailure):
            raise CsqlError(f"the scaling cell {job.method} n={job.n} failed: {row.reason}")
    return rows  # type: ignore[return-value]


def csv_text(rows: Sequence[ScalingRow]) -> str:
    """``method,blocks,trials_to_all_optimal,steps,wall_seconds,peak_rss_mb,population`` (empty trials: cap)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(COLUMNS)
    for r in rows:
        writer.writerow([r.method, r.blocks, "" if r.trials is None else r.trials, r.steps, f"{r.wall_seconds:.3f}",
                         f"{r.peak_rss_mb:.1f}", r.population])
    return out.getvalue()


def figure(rows: Sequence[ScalingRow], max_trials: int) -> Figure:
    """Trials to all-optimal against n per method, log scale; capped cells drawn hollow at the cap."""
    from csql_sim.jobs.plots import new_figure

    fig = new_figure(6, 4.2)
    ax = fig.subplots()
    for method in dict.fromkeys(r.method for r in rows):
        mine = [r for r in rows if r.method == method]
        line = ax.plot([r.blocks for r in mine], [r.trials or max_trials for r in mine], marker="o",
                       label=method.upper())[0]
        capped = [r for r in mine if r.trials is None]
        ax.scatter([r.blocks for r in capped], [max_trials] * len(capped), s=90, facecolors="white",
                   edgecolors=line.get_color(), zorder=3)
    ax.set_yscale("log")
    ax.set_xlabel("blocks n")
    ax.set_ylabel("trials until every pair is planned optimally")
    if any(r.trials is None for r in rows):
        ax.set_title(f"hollow: not reached within {max_trials} trials")
    else:
        ax.set_title(f"every cell reached all pairs optimal (cap {max_trials} trials)")
    ax.set_xticks(sorted({r.blocks for r in rows}))
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def png_bytes(rows: Sequence[ScalingRow], max_trials: int) -> bytes:
    """:func:`figure` as PNG bytes (tagged as csql-sim's, :func:`csql_sim.jobs.plots.png_bytes`)."""
    from csql_sim.jobs.plots import png_bytes as figure_bytes

    return figure_bytes(figure(rows, max_trials))


def write_png(path: str | os.PathLike, rows: Sequence[ScalingRow], max_trials: int) -> Path:
    """Write :func:`png_bytes` atomically (kept in the temporary folder if that fails)."""
    return write_or_keep([(path, png_bytes(rows, max_trials))])[0]


def write_outputs(folder: str | os.PathLike, rows: Sequence[ScalingRow], max_trials: int,
                  sidecar: str | None = None) -> list[Path]:
    """Write ``scaling.csv``, ``scaling.png`` and (given its text) ``scaling.json`` into ``folder``.

    Each file is written atomically; whatever cannot be written is kept whole in the
    temporary folder and named in a one-line OutputError.
    """
    outputs: list[tuple[str | os.PathLike, str | bytes]] = [
        (Path(folder) / "scaling.csv", csv_text(rows)), (Path(folder) / "scaling.png", png_bytes(rows, max_trials))]
    if sidecar is not None:
        outputs.append((Path(folder) / "scaling.json", sidecar))
    return write_or_keep(outputs)
