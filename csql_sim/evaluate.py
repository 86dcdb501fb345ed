"""Sim-in-the-loop evaluation: many physical episodes in parallel, with a summary report."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from tqdm import tqdm

from csql_sim.errors import CsqlError
from csql_sim.files import write_or_keep
from csql_sim.notation import parse_config
from csql_sim.pairs import sample_ranks, selected_pairs
from csql_sim.policy import Policy, load_policy
from csql_sim.workers import worker_count, worker_pool
from csql_sim.world import all_states
from csql_sim.world_model import WorldModel


@dataclass(frozen=True)
class EpisodeSpec:
    """One physical episode to run.

    Attributes:
        start: start configuration (notation).
        goal: goal configuration (notation).
        seed: the episode's seed.
    """

    start: str
    goal: str
    seed: int


@dataclass(frozen=True, kw_only=True)
class EpisodeSummary:
    """What one worker sends back about one episode (built by keyword)."""

    start: str
    goal: str
    seed: int
    success: bool
    reason: str
    optimal: bool = False
    length: int = 0
    optimal_length: int = 0
    sim_seconds_per_action: float = 0.0
    mismatches: int = 0
    events: int = 0


@dataclass
class EvalReport:
    """Aggregate of an evaluation run."""

    episodes: int = 0
    successes: int = 0
    optimal: int = 0
    mean_sim_seconds_per_action: float = 0.0
    mismatches: int = 0
    perturbations: int = 0
    failures: list[dict] = field(default_factory=list)

    @property
    def success_rate(self) -> float:
        """Successes over episodes (0 for no episodes)."""
        return self.successes / self.episodes if self.episodes else 0.0

    def to_dict(self) -> dict:
        """The JSON document of ``--json``."""
        return {
            "episodes": self.episodes,
            "successes": self.successes,
            "success_rate": self.success_rate,
            "optimal": self.optimal,
            "mean_sim_seconds_per_action": self.mean_sim_seconds_per_action,
            "failures": self.failures,
        }

    def text(self) -> str:
        """A human-readable summary."""
        lines = [
            f"episodes: {self.episodes}",
            f"success rate: {self.success_rate:.4f} ({self.successes}/{self.episodes})",
            f"optimal-length plans among successes: {self.optimal}/{self.successes}",
            f"mean simulated seconds per action: {self.mean_sim_seconds_per_action:.3f}",
            f"perturbation events (nudges, drops): {self.perturbations}",
            f"perception vs world-model mismatches (logged, recovered from): {self.mismatches}",
        ]
        for f in self.failures:
            lines.append(f"FAILED start={f['start']} goal={f['goal']} seed={f['seed']}: {f['reason']}")
        return "\n".join(lines)


def make_specs(n: int, pairs: str | int = "all", seeds: int = 1, sample_seed: int = 0) -> list[EpisodeSpec]:
    """Ordered (start, goal) pairs of distinct states, each with seeds 0..seeds-1.

    A sample of K pairs costs O(K) (:mod:`csql_sim.pairs`): the pairs are never all listed,
    and the sample is the one the enumerating version drew.

    Args:
        n: number of blocks.
        pairs: ``"all"`` or the size of a seeded random sample of pairs.
        seeds: episodes per pair; episode k of the pair of rank i has seed ``i * seeds + k``.
        sample_seed: seeds the sample of pairs.
    """
    if pairs != "all":
        sample_ranks(1, pairs)  # validates K before the states are built
    if seeds < 1:
        raise CsqlError(f"--seeds must be a positive integer, got {seeds}")
    states = all_states(n)
    # every episode gets its own seed (pair rank x seeds + k), so perturbations differ across pairs
    return [EpisodeSpec(start=states[s].notation(), goal=states[g].notation(), seed=r * seeds + k)
            for r, s, g in selected_pairs(len(states), pairs, sample_seed) for k in range(seeds)]


class EpisodeRunner:
    """Runs episode specs with one policy and one world model, and summarises each.

    Args:
        policy: the policy every episode follows.
        n: number of blocks (the world model is built once, for all episodes).
        perturb: jitter start scenes, nudge cubes, drop carried cubes.
        perception: ``"pose"`` or ``"camera"``.
    """

    def __init__(self, policy: Policy, n: int, perturb: bool, perception: str) -> None:
        self.policy = policy
        self.world_model = WorldModel.for_blocks(n)
        self.perturb = perturb
        self.perception = perception

    def run(self, spec: EpisodeSpec) -> EpisodeSummary:
        """Run one physical episode; a CsqlError becomes a failed summary with its message."""
        from csql_sim.sim.executor import run_physical_episode

        try:
            r = run_physical_episode(parse_config(spec.start), parse_config(spec.goal), self.policy, seed=spec.seed,
                                     perturb=self.perturb, perception=self.perception,
                                     world_model=self.world_model)
        except CsqlError as exc:
            return EpisodeSummary(start=spec.start, goal=spec.goal, seed=spec.seed, success=False, reason=str(exc))
        return EpisodeSummary(start=spec.start, goal=spec.goal, seed=spec.seed, success=r.success, reason=r.reason,
                              optimal=r.optimal, length=r.length, optimal_length=r.optimal_length,
                              sim_seconds_per_action=r.sim_seconds_per_action, mismatches=len(r.mismatches),
                              events=sum(1 for e in r.events if "skipped" not in e))


_WORKER_RUNNER: EpisodeRunner | None = None  # the one runner of an evaluation worker process


def _init_worker(rules: str | None, n: int, perturb: bool, perception: str) -> None:
    """Pool initializer: the worker process's EpisodeRunner, which lives as long as the worker."""
    global _WORKER_RUNNER
    _WORKER_RUNNER = EpisodeRunner(load_policy(rules, n), n, perturb, perception)


def _run_in_worker(spec: EpisodeSpec) -> EpisodeSummary:
    assert _WORKER_RUNNER is not None, "evaluation worker started without _init_worker"
    return _WORKER_RUNNER.run(spec)


def evaluate(n: int = 3, pairs: str | int = "all", seeds: int = 1, perturb: bool = False,
             workers: int | None = None, rules: str | None = None, perception: str = "pose",
             progress: bool = True) -> EvalReport:
    """Run physical episodes for every start/goal pair in parallel processes and summarise them.

    Args:
        n: number of blocks.
        pairs: ``"all"`` or the size of a seeded sample of start/goal pairs.
        seeds: episodes per pair (each episode has its own seed, reported with failures).
        perturb: jitter start scenes, nudge cubes, drop carried cubes.
        workers: processes (default: every core; at most one per episode). They die with
            this process; an exception (Ctrl-C) ends them at once.
        rules: a rule-base file; the BFS planner when None.
        perception: ``"pose"`` or ``"camera"``.
        progress: show a tqdm bar on stderr.
    """
    policy = load_policy(rules, n)  # fail fast on a bad file, before starting workers
    specs = make_specs(n, pairs, seeds)
    if workers is not None and workers < 1:
        raise CsqlError(f"--workers must be positive, got {workers}")
    workers = worker_count(workers, len(specs))
    init = (rules, n, perturb, perception)
    bar = tqdm(total=len(specs), desc="episodes", unit="ep", disable=not progress)
    summaries: list[EpisodeSummary] = []
    try:
        if workers == 1:
            runner = EpisodeRunner(policy, n, perturb, perception)
            for spec in specs:
                summaries.append(runner.run(spec))
                bar.update()
        else:
            with worker_pool(workers, _init_worker, init) as pool:
                for summary in pool.map(_run_in_worker, specs, chunksize=max(1, len(specs) // (workers * 16))):
                    summaries.append(summary)
                    bar.update()
    finally:
        bar.close()
    return summarise(summaries)


def summarise(summaries: list[EpisodeSummary]) -> EvalReport:
    """Aggregate episode summaries into a report."""
    report = EvalReport(episodes=len(summaries))
    spa = [s.sim_seconds_per_action for s in summaries if s.length]
    report.mean_sim_seconds_per_action = float(np.mean(spa)) if spa else 0.0
    for s in summaries:
        report.successes += s.success
        report.optimal += s.optimal
        report.mismatches += s.mismatches
        report.perturbations += s.events
        if not s.success:
            report.failures.append({"start": s.start, "goal": s.goal, "seed": s.seed, "reason": s.reason})
    return report


def write_json(report: EvalReport, path: str | os.PathLike) -> Path:
    """Write the report's JSON atomically (kept in the temporary folder if that fails)."""
    return write_or_keep([(path, json.dumps(report.to_dict(), indent=1) + "\n")])[0]
