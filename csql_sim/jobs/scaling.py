"""The scaling study: trials until the greedy plans are optimal for every pair, per n, method and mode.

Each (n, method, mode) trains one agent from the seed on random tasks, with the
temperature reaching its floor after 60% of ``max_trials``, and checks after every 1% of
``max_trials`` how many pairs its greedy policy plans optimally (a pair is optimal when
every greedy step on its path lowers the BFS distance: :mod:`csql_sim.core.model.optimal_pairs`).
The cell is empty when ``max_trials`` is reached first. CS-QL runs in three modes
(:data:`MODES`), the other methods in ``trials`` only:

* ``trials``: the trials alone (no replay, no sweep): learning from trials;
* ``replay``: before each check, a replay phase of the transitions the trials experienced
  (:mod:`csql_sim.learners.paper.replay`, hindsight relabelling, at most :data:`REPLAY_RATIO`
  backups per experienced step; reference engine): learning from experience alone;
* ``sweep``: before each check, the sweep through the world model (value iteration):
  planning with the model, which needs hardly any trials.

Version 2 of the CSV and JSON (this one) counts optimal pairs on the policy graph and adds
the mode and the phase columns; version 1 counted optimal first steps.

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

from csql_sim.core.model.optimal_pairs import count_optimal_pairs, count_optimal_steps
from csql_sim.infra.backends import Backend, TaskFailure, map_tasks
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import write_or_keep
from csql_sim.learners.paper import Learner, default_params
from csql_sim.learners.training import make_learner

if TYPE_CHECKING:
    from matplotlib.figure import Figure

COLUMNS = ("method", "mode", "blocks", "trials_to_all_optimal", "steps", "wall_seconds", "peak_rss_mb",
           "population", "optimal_pairs", "pairs", "optimal_steps", "experienced_pairs", "legal_pairs",
           "replay_backups", "sweep_backups")
CHECKS = 100
VERSION = 2
"""The version of ``scaling.csv`` and ``scaling.json`` (see the module)."""
MODES = ("trials", "replay", "sweep")
MODE_LABELS = {"trials": "trials alone", "replay": "experience replay", "sweep": "sweep (value iteration)"}
REPLAY_RATIO = 4.0
"""The ``replay`` mode's cap: replay backups per experienced step."""


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
    mode: str = "trials"
    optimal_steps: int = 0
    experienced_pairs: int = 0
    legal_pairs: int = 0
    replay_backups: int = 0
    sweep_backups: int = 0


def optimal_pairs(learner: Learner) -> int:
    """How many ordered pairs the learner's greedy policy (:meth:`Learner.greedy_table`) plans optimally."""
    return count_optimal_pairs(learner.greedy_table().best, learner.n)


def _mode_params(method: str, n: int, max_trials: int, mode: str) -> dict:
    """The overrides of a cell: the temperature schedule, and CS-QL's sweep and replay by ``mode``."""
    if mode not in MODES:
        raise CsqlError(f"unknown mode {mode!r}; choose from {', '.join(MODES)}")
    base = default_params(method)
    overrides: dict = {"t_decay": (base.t_min / base.t0) ** (1.0 / (0.6 * max_trials))}
    if method in ("cs-ql", "xcs-ql"):
        overrides["sweep"] = mode == "sweep"
        overrides["sweep_backup_all"] = n > 3
        overrides["replay_ratio"] = REPLAY_RATIO if mode == "replay" else 0.0
    elif mode != "trials":
        raise CsqlError(f"{method} has no replay or sweep: only the mode trials applies")
    return overrides


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


def run_cell(method: str, n: int, seed: int, max_trials: int, engine: str | None = None,
             mode: str = "trials") -> ScalingRow:
    """Train one agent until all pairs are optimal or ``max_trials``; its row.

    ``engine``: as :func:`~csql_sim.learners.training.tabular.make_learner`'s (None: the array
    engine where the method has one; the reference for ``replay``); trials and steps do
    not depend on it. ``mode``: one of :data:`MODES` (see the module).
    """
    overrides = _mode_params(method, n, max_trials, mode)
    reset = reset_peak_rss()
    learner = make_learner(method, n, overrides, seed=seed, engine=engine)
    count = len(learner.world.states)
    every = max(1, max_trials // CHECKS)
    found: list[int] = []
    spent = [0.0]

    def check(k: int) -> None:
        if (k + 1) % every == 0:
            if mode == "replay":
                learner.replay()
            elif mode == "sweep":
                learner.sweep()
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
    seen = learner.experience_report() if hasattr(learner, "experience_report") else {}
    return ScalingRow(method, n, trials if reached else None, learner.t, wall, good, count * (count - 1), peak,
                      population, mode, count_optimal_steps(learner.greedy_table().best, n),
                      seen.get("experienced_pairs", 0), seen.get("legal_pairs", 0), seen.get("replay_backups", 0),
                      getattr(learner, "backups", learner.t) - seen.get("experienced_steps", learner.t))


@dataclass(frozen=True)
class CellJob:
    """One (method, n) cell to run."""

    method: str
    n: int
    seed: int
    max_trials: int
    mode: str = "trials"


def _warm_up(methods: tuple[str, ...]) -> None:
    """Worker setup: load the methods' engines (compiling the array engines' kernels) before any cell is timed."""
    for method in methods:
        make_learner(method, 2, engine=None).train(1)


def _run_job(job: CellJob) -> ScalingRow:
    return run_cell(job.method, job.n, job.seed, job.max_trials, mode=job.mode)


def run_scaling(blocks: Sequence[int], methods: Sequence[str], seed: int = 0, max_trials: int = 20_000,
                progress: bool = False, backend: Backend | None = None,
                modes: Sequence[str] = ("trials",)) -> list[ScalingRow]:
    """Every (n, method, mode) cell in order; ``modes`` (of :data:`MODES`) apply to CS-QL and XCS-QL.

    ``backend`` (default: one cell after another in this process, so that no two cells
    share the cores while they are timed) may run cells in parallel, on Ray too; trials
    and steps do not depend on it, wall seconds do.
    """
    jobs = [CellJob(m, n, seed, max_trials, mode) for n in blocks for m in methods
            for mode in (modes if m in ("cs-ql", "xcs-ql") else ("trials",))]
    rows = map_tasks(_run_job, jobs, backend or Backend(workers=1), setup=_warm_up,
                     setup_args=(tuple(dict.fromkeys(methods)),), progress=progress, desc="scaling", unit="cell")
    for job, row in zip(jobs, rows, strict=True):
        if isinstance(row, TaskFailure):
            raise CsqlError(f"the scaling cell {job.method} ({job.mode}) n={job.n} failed: {row.reason}")
    return rows  # type: ignore[return-value]


def csv_text(rows: Sequence[ScalingRow]) -> str:
    """:data:`COLUMNS`, a row per cell (empty trials: the cap was reached)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(COLUMNS)
    for r in rows:
        writer.writerow([r.method, r.mode, r.blocks, "" if r.trials is None else r.trials, r.steps,
                         f"{r.wall_seconds:.3f}", f"{r.peak_rss_mb:.1f}", r.population, r.optimal_pairs, r.pairs,
                         r.optimal_steps, r.experienced_pairs, r.legal_pairs, r.replay_backups, r.sweep_backups])
    return out.getvalue()


def figure(rows: Sequence[ScalingRow], max_trials: int) -> Figure:
    """Trials to all-optimal against n per method, log scale; capped cells drawn hollow at the cap."""
    from csql_sim.jobs.plots import new_figure

    fig = new_figure(6, 4.2)
    ax = fig.subplots()
    series = list(dict.fromkeys((r.method, r.mode) for r in rows))
    for i, (method, mode) in enumerate(series):  # side by side per n
        shift = (i - (len(series) - 1) / 2) * 0.08
        mine = [r for r in rows if (r.method, r.mode) == (method, mode)]
        line = ax.plot([r.blocks + shift for r in mine], [r.trials or max_trials for r in mine], marker="o",
                       label=f"{method.upper()}, {MODE_LABELS[mode]}")[0]
        capped = [r for r in mine if r.trials is None]
        ax.scatter([r.blocks + shift for r in capped], [max_trials] * len(capped), s=90, facecolors="white",
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
