"""Figure 7: test-task curves of the four learners, averaged over cycles run in parallel.

Each cycle is one fresh agent trained for ``trials`` random tasks with the test task
every 50 trials (:meth:`csql_sim.learners.paper.learner.Learner.train`). Cycle ``c`` of every
method draws from ``numpy.random.SeedSequence(seed).spawn(cycles)[c]``, so results do
not depend on the number of worker processes.
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from csql_sim.core.model.search import distance
from csql_sim.core.model.task import test_task
from csql_sim.infra.backends import Backend, TaskFailure, map_tasks
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import write_or_keep
from csql_sim.infra.provenance import provenance
from csql_sim.infra.workers import worker_count
from csql_sim.learners.paper import CommonParams, Curve, resolve_params
from csql_sim.learners.training import METHODS, PAPER_METHODS, make_learner

if TYPE_CHECKING:
    from matplotlib.figure import Figure

CSV_COLUMNS = ("method", "trial", "steps_mean", "steps_std", "value_mean", "value_std")


@dataclass(frozen=True)
class MethodResult:
    """One method's curves over cycles.

    Attributes:
        method: the learner's name.
        trials: the trial index of each test-task point.
        steps: test-task steps, shape (cycles, points).
        values: mean Q-value (or strength) per step, shape (cycles, points).

    """

    method: str
    trials: tuple[int, ...]
    steps: np.ndarray
    values: np.ndarray

    @property
    def steps_mean(self) -> np.ndarray:
        return self.steps.mean(axis=0)

    def first_optimal(self, optimal: int) -> int | None:
        """The first test point at which the mean steps over cycles equal ``optimal``."""
        for trial, mean in zip(self.trials, self.steps_mean, strict=True):
            if mean <= optimal + 1e-9:
                return trial
        return None


@dataclass(frozen=True)
class ExperimentResult:
    """All methods of one experiment."""

    methods: tuple[MethodResult, ...]
    cycles: int
    trials: int
    seed: int
    optimal: int
    n: int = 3
    test_start: str = "CBA"
    test_goal: str = "BAC"
    params: dict[str, CommonParams] = field(default_factory=dict)
    workers: int = 1

    @property
    def test_task_name(self) -> str:
        """The test task as ``start -> goal`` in the configuration notation."""
        return f"{self.test_start} -> {self.test_goal}"

    def provenance(self) -> dict:
        """Package version and every parameter in force (learner parameters with overrides applied)."""
        return provenance(methods=[r.method for r in self.methods], cycles=self.cycles, trials=self.trials,
                          seed=self.seed, blocks=self.n, workers=self.workers, test_task=self.test_task_name,
                          learner_params=self.params)

    def to_dict(self) -> dict:
        """The JSON report (format ``csql-sim experiment report``, version 1): task, summary, provenance."""
        methods = []
        for r in self.methods:
            mean = r.steps.mean(axis=0)
            methods.append({"method": r.method, "initial_steps": float(mean[0]),
                            "first_optimal_trial": r.first_optimal(self.optimal), "final_steps": float(mean[-1]),
                            "min_steps": float(mean.min()), "final_value": float(r.values.mean(axis=0)[-1])})
        return {"format": "csql-sim experiment report", "version": 1,
                "blocks": self.n, "test_task": {"start": self.test_start, "goal": self.test_goal,
                                                "optimal_length": self.optimal},
                "cycles": self.cycles, "trials": self.trials, "seed": self.seed, "methods": methods,
                "provenance": self.provenance()}


def run_cycle(method: str, trials: int, seed: np.random.SeedSequence, n: int, params: CommonParams) -> Curve:
    """One cycle: a fresh learner trained on ``trials`` tasks; its test-task curve."""
    return make_learner(method, n, params, rng=np.random.default_rng(seed), engine=None).train(trials)


def _resolve(methods: Sequence[str], cycles: int, trials: int,
             params: dict[str, CommonParams] | str | os.PathLike | None, n: int = 3) -> dict[str, CommonParams]:
    """Check the experiment's shape and resolve each method's parameters."""
    if not methods:
        raise CsqlError("no methods given")
    for m in methods:
        if m not in METHODS:
            raise CsqlError(f"unknown method {m!r}; choose from {', '.join(METHODS)}")
    if cycles < 1 or trials < 0:
        raise CsqlError(f"need cycles >= 1 and trials >= 0, got {cycles} and {trials}")
    if isinstance(params, dict):
        return {m: resolve_params(m, params.get(m), n) for m in methods}
    return {m: resolve_params(m, params, n) for m in methods}


@dataclass(frozen=True)
class CycleJob:
    """One cycle to run: a method, its parameters and the cycle's seed."""

    method: str
    trials: int
    seed: np.random.SeedSequence
    n: int
    params: CommonParams


def _run_job(job: CycleJob) -> Curve:
    return run_cycle(job.method, job.trials, job.seed, job.n, job.params)


def _run_cycles(jobs: list[CycleJob], backend: Backend, progress: bool) -> list[Curve]:
    """Every job's curve, in job order, on ``backend``; a failed cycle is a one-line error."""
    curves = map_tasks(_run_job, jobs, backend, progress=progress, desc="cycles", unit="cycle")
    for job, curve in zip(jobs, curves, strict=True):
        if isinstance(curve, TaskFailure):
            raise CsqlError(f"a cycle of {job.method} failed: {curve.reason}")
    return curves  # type: ignore[return-value]


def run_experiment(
    methods: Sequence[str] = PAPER_METHODS,
    cycles: int = 50,
    trials: int = 2500,
    seed: int = 0,
    workers: int | None = None,
    n: int = 3,
    params: dict[str, CommonParams] | str | os.PathLike | None = None,
    progress: bool = False,
    backend: Backend | None = None,
) -> ExperimentResult:
    """Run ``cycles`` cycles of each method, in parallel processes when ``workers`` > 1, or on Ray.

    Args:
        methods: learner names (see :data:`csql_sim.learners.training.tabular.METHODS`).
        cycles: independent agents per method.
        trials: training trials per cycle.
        seed: root of the per-cycle seed sequences (cycle c of every method gets the same).
        workers: processes (default ``os.cpu_count()``, at most one per cycle); 1 runs in
            this process. Workers die with this process; an exception (Ctrl-C) ends them at once.
            Overrides ``backend.workers``.
        n: number of blocks.
        params: per-method parameters, or a YAML file (flat or keyed by method).
        progress: show a tqdm bar on stderr.
        backend: where the cycles run (default: a local process pool; or Ray).

    """
    resolved = _resolve(methods, cycles, trials, params, n)
    seeds = np.random.SeedSequence(seed).spawn(cycles)
    jobs = [CycleJob(m, trials, seeds[c], n, resolved[m]) for m in methods for c in range(cycles)]
    backend = backend or Backend()
    if workers is not None:
        backend = Backend(backend.kind, workers, backend.address)
    curves = _run_cycles(jobs, backend, progress)
    workers = worker_count(backend.workers, len(jobs))  # the processes, or a local Ray instance's CPUs
    results = []
    for k, m in enumerate(methods):
        runs = curves[k * cycles : (k + 1) * cycles]
        results.append(MethodResult(method=m, trials=runs[0].trials,
                                    steps=np.array([r.steps for r in runs], dtype=float),
                                    values=np.array([r.values for r in runs], dtype=float)))
    task = test_task(n)
    return ExperimentResult(tuple(results), cycles, trials, seed, distance(task.start, task.goal), n,
                            task.start.notation(), task.goal.notation(), resolved, workers)


def csv_text(result: ExperimentResult) -> str:
    """Figure 7's data: one row per method and test point (std over cycles, ddof 0)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    for r in result.methods:
        s_mean, s_std = r.steps.mean(axis=0), r.steps.std(axis=0)
        v_mean, v_std = r.values.mean(axis=0), r.values.std(axis=0)
        for k, trial in enumerate(r.trials):
            stats = (s_mean[k], s_std[k], v_mean[k], v_std[k])
            writer.writerow([r.method, trial, *(f"{x:.6g}" for x in stats)])
    return out.getvalue()


def write_csv(path: str | os.PathLike, result: ExperimentResult) -> Path:
    """Write :func:`csv_text` atomically (kept in the temporary folder if that fails)."""
    return write_or_keep([(path, csv_text(result))])[0]


def figure7(result: ExperimentResult) -> Figure:
    """Figure 7's two panels (steps; value per step) as a matplotlib figure.

    Each method's mean over cycles is a line with a band of one standard deviation
    (the CSV's std column; in panel (a) cut off at the optimum, which no run can beat);
    the optimum of the test task is a labelled line.
    """
    from csql_sim.jobs.plots import new_figure

    fig = new_figure(11, 4.4)
    ax_steps, ax_value = fig.subplots(1, 2)
    for r in result.methods:
        for ax, data in ((ax_steps, r.steps), (ax_value, r.values)):
            mean, std = data.mean(axis=0), data.std(axis=0)
            (line,) = ax.plot(r.trials, mean, label=r.method.upper())
            # no run can take fewer steps than the optimum: the band stops there
            low = np.maximum(mean - std, result.optimal) if ax is ax_steps else mean - std
            ax.fill_between(r.trials, low, mean + std, color=line.get_color(), alpha=0.15, lw=0)
    ax_steps.axhline(result.optimal, color="black", lw=0.9, ls="--",
                     label=f"optimum: {result.optimal} steps")
    ax_steps.annotate(f"optimum {result.optimal}", (result.trials, result.optimal), textcoords="offset points",
                      xytext=(0, -11), ha="right", fontsize=8)
    ax_steps.set_yscale("log")
    ax_steps.set_xlabel("trial")
    ax_steps.set_ylabel("steps in the test task")
    ax_steps.set_title(f"(a) steps to perform the test task {result.test_task_name}")
    ax_value.set_xlabel("trial")
    ax_value.set_ylabel("average Q-value / strength per step")
    ax_value.set_title("(b) average value per step in the test task")
    for ax in (ax_steps, ax_value):
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle(f"Figure 7: mean and one standard deviation over {result.cycles} cycles of {result.trials} "
                 f"trials ({result.n} blocks)")
    fig.tight_layout()
    return fig


def png_bytes(result: ExperimentResult) -> bytes:
    """Figure 7 (:func:`figure7`) as PNG bytes."""
    from csql_sim.jobs.plots import png_bytes as figure_bytes

    return figure_bytes(figure7(result))


def write_png(path: str | os.PathLike, result: ExperimentResult) -> Path:
    """Draw Figure 7 and write the PNG atomically (kept in the temporary folder if that fails)."""
    return write_or_keep([(path, png_bytes(result))])[0]


def provenance_json(result: ExperimentResult) -> str:
    """The CSV's sidecar JSON: the report of :meth:`ExperimentResult.to_dict`."""
    import json

    return json.dumps(result.to_dict(), indent=1) + "\n"


def write_figure7(folder: str | os.PathLike, result: ExperimentResult) -> list[Path]:
    """Write ``figure7.csv``, its provenance ``figure7.json`` and ``figure7.png`` into ``folder``.

    Raises:
        OutputError: if any cannot be written; every unwritten file is kept in the
            temporary folder and the message says where.
    """
    return write_or_keep([(os.path.join(folder, "figure7.csv"), csv_text(result)),
                          (os.path.join(folder, "figure7.json"), provenance_json(result)),
                          (os.path.join(folder, "figure7.png"), png_bytes(result))])


def summary_lines(result: ExperimentResult) -> list[str]:
    """Per method: initial test-task steps, first trial at the optimum, final steps."""
    lines = [f"test task {result.test_task_name} ({result.n} blocks), optimum: {result.optimal} steps; "
             f"{result.cycles} cycles x {result.trials} trials"]
    for r in result.methods:
        mean = r.steps.mean(axis=0)
        first = r.first_optimal(result.optimal)
        lines.append(
            f"{r.method:<9} initial {mean[0]:7.1f} steps  first optimal (mean = {result.optimal}) at trial "
            f"{first if first is not None else 'never':>5}  final {mean[-1]:6.1f} steps  "
            f"min {mean.min():6.1f}  final value {r.values.mean(axis=0)[-1]:.3f}"
        )
    return lines
