"""Sim-in-the-loop evaluation: many physical episodes in parallel, with a summary report.

Up to six blocks the pairs come from the enumerated world (all of them, or a seeded
sample) and the policy is BFS or a rule file. For 7..30 cubes (the arm's limit) the
states are relational, K pairs are drawn by counting (:mod:`csql_sim.core.model.pairs`), the
policy is lifted (lifted rules or ``gn1``) and optimal lengths are the exact optimum's.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from csql_sim import __version__
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.policies.policy import Policy
from csql_sim.core.policies.sharded_policy import GoalColumns, ShardedPolicy
from csql_sim.infra.backends import Backend, TaskFailure, map_tasks
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import write_or_keep
from csql_sim.infra.provenance import provenance, rules_source
from csql_sim.infra.ray_session import ray_session
from csql_sim.infra.workers import worker_count
from csql_sim.jobs.baselines import NAMED_POLICIES
from csql_sim.jobs.episodes import Episodes, EpisodeSpec, batches, plan_episodes
from csql_sim.jobs.episodes import make_specs as make_specs  # re-exported: the episodes of an evaluation
from csql_sim.jobs.job_memory import check_episodes
from csql_sim.sim.world import cube_legend

BATCH_EPISODES = 4096
"""Episodes handed to the workers at once: the specs are drawn a batch at a time, never all listed."""


@dataclass(frozen=True)
class PerturbationEvent:
    """A perturbation that struck an episode: during which action (0-based), and what it did."""

    step: int
    what: str


@dataclass(frozen=True, kw_only=True)
class EpisodeSummary:
    """What one worker sends back about one episode (built by keyword; one ``runs`` record)."""

    start: str
    goal: str
    seed: int
    success: bool
    reason: str
    optimal: bool = False
    length: int = 0
    optimal_length: int = 0
    sim_seconds_per_action: float = 0.0
    sim_seconds: float = 0.0
    mismatches: int = 0
    perturbations: int = 0
    events: tuple[PerturbationEvent, ...] = ()

    def to_dict(self) -> dict:
        """The episode's ``runs`` record."""
        return {
            "start": self.start, "goal": self.goal, "seed": self.seed, "success": self.success,
            "reason": self.reason, "length": self.length, "optimal_length": self.optimal_length,
            "sim_seconds": round(self.sim_seconds, 6), "mismatches": self.mismatches,
            "perturbations": self.perturbations,
            "events": [{"step": e.step, "what": e.what} for e in self.events],
        }


def plan_length_stats(runs: list[EpisodeSummary]) -> dict:
    """Executed against optimal plan length over the successful episodes."""
    ok = [r for r in runs if r.success]
    if not ok:
        return {"episodes": 0, "mean_length": None, "mean_optimal_length": None, "mean_excess": None,
                "max_excess": None, "excess_histogram": {}}
    excess = [r.length - r.optimal_length for r in ok]
    return {
        "episodes": len(ok),
        "mean_length": float(np.mean([r.length for r in ok])),
        "mean_optimal_length": float(np.mean([r.optimal_length for r in ok])),
        "mean_excess": float(np.mean(excess)),
        "max_excess": max(excess),
        "excess_histogram": {str(k): excess.count(k) for k in sorted(set(excess))},
    }


@dataclass
class EvalReport:
    """Aggregate of an evaluation run.

    Attributes:
        runs: one summary per episode, in spec order.
        config: what was run (rules file and hash, blocks, perception, ...; see :func:`evaluate`).
    """

    episodes: int = 0
    successes: int = 0
    optimal: int = 0
    mean_sim_seconds_per_action: float = 0.0
    mismatches: int = 0
    perturbations: int = 0
    failures: list[dict] = field(default_factory=list)
    runs: list[EpisodeSummary] = field(default_factory=list)
    config: dict = field(default_factory=dict)
    legend: dict[str, str] = field(default_factory=dict)

    @property
    def success_rate(self) -> float:
        """Successes over episodes (0 for no episodes)."""
        return self.successes / self.episodes if self.episodes else 0.0

    def to_dict(self) -> dict:
        """The JSON document of ``--json`` (format ``csql-sim evaluation report``, version 1)."""
        return {
            "format": "csql-sim evaluation report",
            "version": 1,
            "config": self.config,
            "legend": self.legend,
            "episodes": self.episodes,
            "successes": self.successes,
            "success_rate": self.success_rate,
            "optimal": self.optimal,
            "mean_sim_seconds_per_action": self.mean_sim_seconds_per_action,
            "perturbations": self.perturbations,
            "mismatches": self.mismatches,
            "plan_length": plan_length_stats(self.runs),
            "failures": self.failures,
            "runs": [r.to_dict() for r in self.runs],
        }

    def text(self) -> str:
        """A human-readable summary."""
        lines = [
            *(["legend: " + ", ".join(f"{k} = {v}" for k, v in self.legend.items())] if self.legend else []),
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


class EpisodeRunner:
    """Runs episode specs with one policy and one world model, and summarises each.

    Args:
        policy: the policy every episode follows.
        n: number of blocks (the world model is built once, for all episodes).
        perturb: jitter start scenes, nudge cubes, drop carried cubes.
        perception: ``"pose"`` or ``"camera"``.
        camera_noise: (depth m, colour 8-bit levels) standard deviations of camera noise.
    """

    def __init__(self, policy: Policy, n: int, perturb: bool, perception: str,
                 camera_noise: tuple[float, float] = (0.0, 0.0)) -> None:
        from csql_sim.sim.perception import CameraNoise
        from csql_sim.sim.world import world_model_for

        self.policy = policy
        self.n = n
        self.world_model = world_model_for(n)
        self.perturb = perturb
        self.perception = perception
        self.camera_noise = CameraNoise(*camera_noise)

    def run(self, spec: EpisodeSpec) -> EpisodeSummary:
        """Run one physical episode; a CsqlError becomes a failed summary with its message."""
        from csql_sim.sim.control import run_physical_episode
        from csql_sim.sim.world import parse_arm_state

        try:
            start, goal = parse_arm_state(spec.start), parse_arm_state(spec.goal)
            r = run_physical_episode(start, goal, self.policy, seed=spec.seed,
                                     perturb=self.perturb, perception=self.perception,
                                     world_model=self.world_model, camera_noise=self.camera_noise)
        except CsqlError as exc:
            return EpisodeSummary(start=spec.start, goal=spec.goal, seed=spec.seed, success=False, reason=str(exc))
        events = tuple(PerturbationEvent(k, e) for k, e in zip(r.event_steps, r.events, strict=True)
                       if "skipped" not in e)
        return EpisodeSummary(start=spec.start, goal=spec.goal, seed=spec.seed, success=r.success, reason=r.reason,
                              optimal=r.optimal, length=r.length, optimal_length=r.optimal_length,
                              sim_seconds_per_action=r.sim_seconds_per_action, sim_seconds=r.sim_seconds,
                              mismatches=len(r.mismatches), perturbations=len(events), events=events)


@dataclass(frozen=True)
class PolicyData:
    """The policy of an evaluation as data for its workers, so that no worker reads the rule file.

    Plain bytes, not an array: worker setup arguments are compared with ``==``.

    Attributes:
        n: number of blocks.
        best: a rule file's :class:`~csql_sim.core.policies.greedy_table.GreedyTable` ``best`` array as
            bytes, or None for the BFS planner.
        dtype: the array's dtype (``numpy.dtype.str``).
        goals: for a sharded rule base, the goals whose columns ``best`` holds
            (``best[k * S + state]`` for ``goals[k]``); empty: ``best`` is the whole table.
        named: a named baseline policy (:data:`NAMED_POLICIES`, e.g. ``"gn1"``), or "".
        lifted: a lifted policy read from a rule file (any n; its ``blocks`` is None), or None.
    """

    n: int
    best: bytes | None = None
    dtype: str = ""
    goals: tuple[int, ...] = ()
    named: str = ""
    lifted: Any = None

    @classmethod
    def read(cls, rules: str | os.PathLike | None, n: int, progress: bool = False,
             goals: tuple[int, ...] = (), named: str | None = None) -> PolicyData:
        """Read the rule file ``rules`` (once; BFS when None and no ``named`` policy, reading nothing).

        A sharded rule base is read only for ``goals`` (the goals of the episodes): their
        shards, one column of greedy actions per goal. Past six blocks only a lifted policy
        will do: BFS and ground rule files are refused.

        Raises:
            CsqlError: if the file is missing, corrupt, foreign, or for another number of blocks.
        """
        if named:
            if named not in NAMED_POLICIES:
                raise CsqlError(f"unknown policy {named!r}; named policies: {', '.join(NAMED_POLICIES)}")
            if rules is not None:
                raise CsqlError(f"give a rule file or the named policy {named!r}, not both")
            return cls(n, named=named)
        table = load_policy(rules, n, progress=progress)  # past six blocks, lifted rules only
        if rules is None:
            return cls(n)
        if getattr(table, "blocks", 0) is None:  # lifted rules: any number of blocks
            return cls(n, lifted=table)
        if isinstance(table, ShardedPolicy):
            wanted = tuple(sorted(set(goals)))
            columns = np.ascontiguousarray(table.columns(wanted))
            return cls(table.n, columns.tobytes(), columns.dtype.str, wanted)
        assert isinstance(table, GreedyTable), "a rule file's policy is a greedy table"
        best = np.ascontiguousarray(table.best)
        return cls(table.n, best.tobytes(), best.dtype.str)

    def policy(self) -> Policy:
        """The policy itself (a greedy table over the shipped array, a lifted or named policy, or BFS)."""
        if self.named:
            return NAMED_POLICIES[self.named]()
        if self.lifted is not None:
            return self.lifted
        if self.best is None:
            return load_policy(None, self.n)
        best = np.frombuffer(self.best, np.dtype(self.dtype))
        if self.goals:
            return GoalColumns(self.n, self.goals, best)
        return GreedyTable(self.n, best)


_WORKER_RUNNER: EpisodeRunner | None = None  # the one runner of an evaluation worker process


def _init_worker(policy: PolicyData, n: int, perturb: bool, perception: str,
                 camera_noise: tuple[float, float] = (0.0, 0.0)) -> None:
    """Worker setup (again only for other arguments): the process's EpisodeRunner, which lives as long as it."""
    global _WORKER_RUNNER
    _WORKER_RUNNER = EpisodeRunner(policy.policy(), n, perturb, perception, camera_noise)


def _run_in_worker(spec: EpisodeSpec) -> EpisodeSummary:
    assert _WORKER_RUNNER is not None, "evaluation worker started without _init_worker"
    return _WORKER_RUNNER.run(spec)


def evaluate(n: int = 3, pairs: str | int = "all", seeds: int = 1, perturb: bool = False,
             workers: int | None = None, rules: str | None = None, perception: str = "pose",
             progress: bool = True, seed: int = 0, camera_noise: tuple[float, float] = (0.0, 0.0),
             backend: Backend | None = None, planner: str | None = None) -> EvalReport:
    """Run physical episodes for every start/goal pair in parallel and summarise them.

    Args:
        n: number of blocks, 2..30 (past six: relational states, a lifted policy, sampled pairs).
        pairs: ``"all"`` or the size of a seeded sample of start/goal pairs (past six blocks
            K only, drawn uniformly by counting).
        seeds: episodes per pair (each episode has its own seed, reported with failures).
        perturb: jitter start scenes, nudge cubes, drop carried cubes.
        workers: processes (default: every core; at most one per episode), or CPUs of a
            local Ray instance; overrides ``backend.workers``.
        rules: a rule-base file; the BFS planner when None (and no ``planner``).
        perception: ``"pose"`` or ``"camera"``.
        progress: show a tqdm bar on stderr.
        seed: seeds the sample of pairs (``pairs`` = K).
        camera_noise: (depth m, colour 8-bit levels) standard deviations of camera noise.
        backend: where the episodes run (default: a local process pool whose workers die
            with this process; or Ray). A task that fails with a CsqlError, or whose
            worker dies, is reported as a failed episode; any other exception (a bug)
            propagates.
        planner: a named baseline policy instead of a rule file (``"gn1"``).

    Raises:
        CsqlError: bad perception mode, camera noise (or noise without camera perception), rule file,
            policy, number of cubes or pairs, or more episodes than their summaries' memory allows
            (:func:`csql_sim.jobs.job_memory.check_episodes`), before any episode.
    """
    from csql_sim.sim.control import check_perception
    from csql_sim.sim.perception import CameraNoise
    from csql_sim.sim.world import check_arm_blocks

    check_arm_blocks(n)
    check_perception(perception, n)  # bad options fail once, here, not in every episode
    CameraNoise(*camera_noise)
    if perception != "camera" and any(camera_noise):  # pose perception takes no images: the noise would be lost
        raise CsqlError(f"camera noise {tuple(camera_noise)} needs perception 'camera', not {perception!r}")
    episodes = plan_episodes(n, pairs, seeds, sample_seed=seed)  # checked and counted, none listed
    check_episodes(episodes.count, episodes.pair_total, seeds)  # every summary must fit, or no episode runs
    goals = episodes.goal_indices() if rules is not None else ()
    policy = PolicyData.read(rules, n, progress=progress, goals=goals, named=planner)  # the one read
    backend = backend or Backend()
    if workers is not None:
        backend = Backend(backend.kind, workers, backend.address)
    setup_args = (policy, n, perturb, perception, tuple(camera_noise))
    report = summarise(run_episodes(episodes, backend, setup_args, progress))
    used = worker_count(backend.workers, episodes.count) if backend.kind == "processes" else None
    report.legend = cube_legend(n)
    report.config = {
        "rules": rules_source(rules), "blocks": n, "perception": perception, "perturb": perturb,
        "camera_noise": list(camera_noise),
        "pairs": pairs, "seeds": seeds, "seed": seed, "workers": used, "backend": backend.kind,
        "address": backend.address, "version": __version__, **({"planner": planner} if planner else {}),
    }
    return report


def run_episodes(episodes: Episodes, backend: Backend, setup_args: tuple, progress: bool) -> list[EpisodeSummary]:
    """Every episode's summary, in order: the specs go to the workers :data:`BATCH_EPISODES` at a time.

    The first episode starts as soon as its batch is drawn; each summary depends on its spec
    alone, so the order of the batches and the number of workers change nothing. A local Ray
    instance is started once for all the batches.
    """
    from contextlib import ExitStack

    from tqdm import tqdm

    out: list[EpisodeSummary] = []
    with ExitStack() as stack:
        if backend.kind == "ray":
            stack.enter_context(ray_session(backend.address, backend.workers, announce=progress))
        bar = stack.enter_context(tqdm(total=episodes.count, desc="episodes", unit="ep", disable=not progress))

        def tick(_: int, result: object) -> object:
            bar.update(1)
            return result

        for batch in batches(episodes, BATCH_EPISODES):
            results = map_tasks(_run_in_worker, batch, backend, setup=_init_worker, setup_args=setup_args,
                                on_result=tick)
            out.extend(_failed(spec, r.reason) if isinstance(r, TaskFailure) else r
                       for spec, r in zip(batch, results, strict=True))
    return out


def _failed(spec: EpisodeSpec, reason: str) -> EpisodeSummary:
    """The summary of an episode whose task failed in its worker."""
    return EpisodeSummary(start=spec.start, goal=spec.goal, seed=spec.seed, success=False, reason=reason)


def summarise(summaries: list[EpisodeSummary]) -> EvalReport:
    """Aggregate episode summaries into a report."""
    report = EvalReport(episodes=len(summaries), runs=list(summaries))
    spa = [s.sim_seconds_per_action for s in summaries if s.length]
    report.mean_sim_seconds_per_action = float(np.mean(spa)) if spa else 0.0
    for s in summaries:
        report.successes += s.success
        report.optimal += s.optimal
        report.mismatches += s.mismatches
        report.perturbations += s.perturbations
        if not s.success:
            report.failures.append({"start": s.start, "goal": s.goal, "seed": s.seed, "reason": s.reason})
    return report


def write_json(report: EvalReport, path: str | os.PathLike) -> Path:
    """Write the report's JSON with its provenance atomically (kept in the temporary folder if that fails)."""
    doc = {**report.to_dict(), "provenance": provenance(**report.config)}
    return write_or_keep([(path, json.dumps(doc, indent=1) + "\n")])[0]
