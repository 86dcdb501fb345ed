"""Sim-in-the-loop evaluation: many physical episodes in parallel, with a summary report.

Up to six blocks the pairs come from the enumerated world (all of them, or a seeded
sample) and the policy is BFS or a rule file. For 7..10 cubes (the arm's limit) the
states are relational, K pairs are drawn by counting (:mod:`csql_sim.core.pairs`), the
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
from csql_sim.core.greedy_table import GreedyTable, load_policy
from csql_sim.core.notation import parse_config
from csql_sim.core.pairs import check_large_pairs, check_sample_size, pair_count, selected_pairs, stream_large_pairs
from csql_sim.core.policy import Policy
from csql_sim.core.sharded_policy import GoalColumns, ShardedPolicy
from csql_sim.core.world import MAX_BLOCKS, BlocksWorld, all_states
from csql_sim.infra.backends import Backend, TaskFailure, map_tasks
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import write_or_keep
from csql_sim.infra.provenance import provenance, rules_source
from csql_sim.infra.workers import worker_count
from csql_sim.learners.gn1 import NAMED_POLICIES


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

    A sample of K pairs costs O(K) (:mod:`csql_sim.core.pairs`): the pairs are never all listed,
    and the sample is the one the enumerating version drew.

    Args:
        n: number of blocks.
        pairs: ``"all"`` or the size of a seeded random sample of pairs.
        seeds: episodes per pair; episode k of the pair of rank i has seed ``i * seeds + k``.
        sample_seed: seeds the sample of pairs.
    """
    if seeds < 1:
        raise CsqlError(f"--seeds must be a positive integer, got {seeds}")
    if n > MAX_BLOCKS:
        return _sampled_specs(n, pairs, seeds, sample_seed)
    states = all_states(n)
    if pairs != "all":
        check_sample_size(pairs, pair_count(len(states)))
    # every episode gets its own seed (pair rank x seeds + k), so perturbations differ across pairs
    return [EpisodeSpec(start=states[s].notation(), goal=states[g].notation(), seed=r * seeds + k)
            for r, s, g in selected_pairs(len(states), pairs, sample_seed) for k in range(seeds)]


def _sampled_specs(n: int, pairs: str | int, seeds: int, sample_seed: int) -> list[EpisodeSpec]:
    """Past six blocks: K pairs drawn uniformly by counting (:func:`check_large_pairs` refuses ``all``)."""
    drawn = stream_large_pairs(n, check_large_pairs(pairs, n), sample_seed)
    return [EpisodeSpec(start=s.notation(), goal=g.notation(), seed=r * seeds + k)
            for r, (s, g) in enumerate(drawn) for k in range(seeds)]


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
        from csql_sim.sim.arm_state import world_model_for
        from csql_sim.sim.rgbd import CameraNoise

        self.policy = policy
        self.n = n
        self.world_model = world_model_for(n)
        self.perturb = perturb
        self.perception = perception
        self.camera_noise = CameraNoise(*camera_noise)

    def run(self, spec: EpisodeSpec) -> EpisodeSummary:
        """Run one physical episode; a CsqlError becomes a failed summary with its message."""
        from csql_sim.sim.arm_state import parse_arm_state
        from csql_sim.sim.executor import run_physical_episode

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
        best: a rule file's :class:`~csql_sim.core.greedy_table.GreedyTable` ``best`` array as
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
        n: number of blocks, 2..10 (past six: relational states, a lifted policy, sampled pairs).
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
        CsqlError: bad perception mode, camera noise, rule file, policy, number of cubes or
            pairs, before any episode.
    """
    from csql_sim.sim.arm_state import check_arm_blocks
    from csql_sim.sim.physical import check_perception
    from csql_sim.sim.rgbd import CameraNoise

    check_arm_blocks(n)
    check_perception(perception)  # bad options fail once, here, not in every episode
    CameraNoise(*camera_noise)
    specs = make_specs(n, pairs, seeds, sample_seed=seed)
    goals = () if n > MAX_BLOCKS else tuple(BlocksWorld.of(n).state_index(parse_config(s.goal)) for s in specs)
    policy = PolicyData.read(rules, n, progress=progress, goals=goals, named=planner)  # the one read
    backend = backend or Backend()
    if workers is not None:
        backend = Backend(backend.kind, workers, backend.address)
    setup_args = (policy, n, perturb, perception, tuple(camera_noise))
    results = map_tasks(_run_in_worker, specs, backend, setup=_init_worker, setup_args=setup_args,
                        progress=progress, desc="episodes", unit="ep")
    report = summarise([_failed(spec, r.reason) if isinstance(r, TaskFailure) else r
                        for spec, r in zip(specs, results, strict=True)])
    used = worker_count(backend.workers, len(specs)) if backend.kind == "processes" else None
    report.config = {
        "rules": rules_source(rules), "blocks": n, "perception": perception, "perturb": perturb,
        "camera_noise": list(camera_noise),
        "pairs": pairs, "seeds": seeds, "seed": seed, "workers": used, "backend": backend.kind,
        "address": backend.address, "version": __version__, **({"planner": planner} if planner else {}),
    }
    return report


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
