"""Goal-sharded training: the goals split into shards, each trained on its own, in parallel.

A goal's Q-classifiers depend only on the trials toward that goal, so CS-QL's array engine
(:class:`~csql_sim.learners.engines.fast_engine.FastCSQL`) trains a *shard* of goals as one engine
restricted to those goals. Shard ``k`` of ``S`` holds the goals ``k * count // S`` ..
``(k + 1) * count // S - 1`` (:func:`~csql_sim.core.files.rulebase_shards.goal_range`), draws its
random stream from ``SeedSequence(seed, spawn_key=(k,))`` and runs its share of the random
training trials (a goal among its own, a start among the other states), then the planning
sweep over its goals. Nothing depends on which worker or backend ran it, so the rule base
(:mod:`csql_sim.core.files.rulebase_shards`) is byte-identical for 1 or 2 workers, local or Ray.

Each shard is written (atomically, with its SHA-256 in the manifest) as soon as it comes
back, so a run that stops early leaves every finished shard; ``resume`` trains the rest.
With one shard this is not the paper's single run (that one also interleaves the test
task); the default is one unsharded engine up to 5 blocks (:func:`default_shards`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import resource
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import numpy as np

from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.files import rulebase_shards as rs
from csql_sim.core.model.search import reverse_bfs
from csql_sim.core.model.transition_table import true_table
from csql_sim.core.state.world import BlocksWorld
from csql_sim.infra.backends import Backend, TaskFailure, map_tasks
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import read_json_file, write_atomic
from csql_sim.infra.provenance import plain, provenance
from csql_sim.infra.workers import worker_count
from csql_sim.learners.engines.fast_engine import FastCSQL, ModelArrays, world_model
from csql_sim.learners.paper.params import CSQLParams

REPORT_VERSION = 2
"""The run report's version: 2 counts optimal pairs on the policy graph (1: first steps) and adds phases."""
MAX_REPORT_BYTES = 1 << 24
"""The largest run-report file read back (each run adds about 1 kB)."""
SHARDS_BY_BLOCKS = {6: 64, 7: 512}
"""Shards by default (one engine below 6 blocks; at 6: 110 goals per shard, a 45 MB file, a worker of about 0.6 GB)."""


def default_shards(n: int) -> int:
    """The number of shards ``train`` uses for n blocks when none is given."""
    return SHARDS_BY_BLOCKS.get(n, 1)


class ShardJob(NamedTuple):
    """What one shard's training needs (all of it determines the shard's content).

    Attributes:
        n: number of blocks.
        params: CS-QL parameters.
        seed: the run's seed (the shard's stream is derived from it and ``index``).
        shards: the number of shards.
        index: this shard.
        trials: the run's random training trials (the shard runs its share).

    """

    n: int
    params: CSQLParams
    seed: int
    shards: int
    index: int
    trials: int


class ShardOutcome(NamedTuple):
    """A trained shard and what was measured while training it (the measures go to the run report)."""

    arrays: rs.ShardArrays | None
    steps: int
    q_classifiers: int
    optimal: int
    pairs: int
    trial_steps: int
    trials_optimal: int
    optimal_steps: int
    experienced_pairs: int
    sweep_backups: int
    seconds: float
    cpu_seconds: float
    peak_rss: int


class SharedModel:
    """The world model's arrays as a worker setup argument, equal by (n, digest) only."""

    def __init__(self, n: int, model: ModelArrays) -> None:
        self.n, self.model = n, model
        h = hashlib.sha256()
        for a in (model.lo, model.action, model.nxt):
            h.update(np.ascontiguousarray(a).tobytes())
        self.digest = h.hexdigest()

    def __eq__(self, other: object) -> bool:
        return isinstance(other, SharedModel) and (self.n, self.digest) == (other.n, other.digest)

    def __hash__(self) -> int:
        return hash((self.n, self.digest))


_MODEL: dict[int, ModelArrays] = {}  # owned by install_model: the world model a worker was given, per n


def install_model(shared: SharedModel) -> None:
    """Worker setup: keep the world model sent once (Ray: through the object store)."""
    _MODEL[shared.n] = shared.model


def shard_trials(trials: int, shards: int, index: int) -> int:
    """Shard ``index``'s share of ``trials`` (the shares add up to ``trials``)."""
    return (index + 1) * trials // shards - index * trials // shards


def shard_rng(seed: int, index: int) -> np.random.Generator:
    """Shard ``index``'s generator: ``SeedSequence(seed, spawn_key=(index,))``."""
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index,)))


def train_shard(job: ShardJob) -> ShardOutcome:
    """Train shard ``job.index``: its random trials, then the sweep over its goals; count its optimal pairs."""
    began, cpu = time.perf_counter(), time.process_time()
    model = _MODEL.get(job.n) or world_model(job.n)
    count = len(model.lo) - 1
    lo, hi = rs.goal_range(count, job.shards, job.index)
    learner = FastCSQL(job.n, job.params, shard_rng(job.seed, job.index), goals=np.arange(lo, hi), model=model,
                        ordered=True)
    if job.params.replay_ratio > 0:
        raise CsqlError("sharded training does not replay experience (replay_ratio must be 0)")
    learner.train(shard_trials(job.trials, job.shards, job.index), test_every=0)
    trial_steps, trials_optimal = learner.t, count_optimal(canonical(learner, lo, hi), model, job.n, lo, hi)[0]
    backups = learner.backups
    learner.sweep()
    arrays = canonical(learner, lo, hi)
    optimal, steps_ok = count_optimal(arrays, model, job.n, lo, hi)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * (1 if sys.platform == "darwin" else 1024)
    return ShardOutcome(arrays, steps=learner.t, q_classifiers=len(arrays.q), optimal=optimal,
                        pairs=(hi - lo) * (count - 1), trial_steps=trial_steps, trials_optimal=trials_optimal,
                        optimal_steps=steps_ok, experienced_pairs=learner.experience_report()["experienced_pairs"],
                        sweep_backups=learner.backups - backups, seconds=time.perf_counter() - began,
                        cpu_seconds=time.process_time() - cpu, peak_rss=peak)


def canonical(learner: FastCSQL, lo: int, hi: int) -> rs.ShardArrays:
    """The engine's Q-classifiers of goals ``lo .. hi - 1``, goal-major and by state (the shard layout)."""
    a = learner.q_arrays()
    count, model = learner.count, learner.model
    node = (a["goal"] - lo) * count + a["state"]
    width = np.diff(model.lo)[a["state"]]
    starts = np.flatnonzero(np.r_[True, (node[1:] != node[:-1])])  # a node's slots are consecutive
    node_key = node[starts]
    order = np.argsort(node_key, kind="stable")
    first = np.full((hi - lo) * count, -1, np.int64)
    born = np.zeros((hi - lo) * count, np.int64)
    sizes = width[starts][order]
    new_first = np.zeros(len(order), np.int64)
    new_first[1:] = np.cumsum(sizes)[:-1]
    first[node_key[order]] = new_first
    born[node_key[order]] = a["born"][starts][order]
    take = np.concatenate([np.arange(s, s + w) for s, w in zip(starts[order], sizes, strict=True)]) \
        if len(order) else np.zeros(0, np.int64)
    return rs.ShardArrays(first, born, a["q"][take], a["error"][take], learner.t)


def count_optimal(arrays: rs.ShardArrays, model: ModelArrays, n: int, lo: int, hi: int) -> tuple[int, int]:
    """Goals ``lo .. hi - 1``: (optimal pairs, optimal first steps), against the true BFS distances.

    A pair is optimal when every greedy step on its path lowers the distance by one
    (decided on the policy graph per goal, in order of distance,
    :mod:`csql_sim.core.model.optimal_pairs`); the second count is of the pairs whose first
    greedy step does, an upper bound of the first.
    """
    table = true_table(n)
    count = table.state_count
    rank = rs.greedy_ranks(arrays.first, arrays.q, np.diff(model.lo), count)
    pairs = steps = 0
    for g in range(lo, hi):
        r = rank[(g - lo) * count:(g - lo + 1) * count]
        states = np.flatnonzero(r >= 0)
        nxt = np.full(count, -1, np.int64)
        nxt[states] = table.next_state[states, model.action[model.lo[states] + r[states]]]
        dist = reverse_bfs(table.predecessors, g)
        step_ok = (nxt >= 0) & (dist[np.maximum(nxt, 0)] == dist - 1) & (dist > 0)
        ok = step_ok.copy()
        order = np.argsort(dist, kind="stable")
        ends = np.searchsorted(dist[order], np.arange(int(dist.max()) + 2))
        for d in range(2, int(dist.max()) + 1):  # by distance: a pair's successor is decided first
            level = order[ends[d]:ends[d + 1]]
            ok[level] = step_ok[level] & ok[nxt[level]]
        pairs, steps = pairs + int(ok.sum()), steps + int(step_ok.sum())
    return pairs, steps


# ---------------------------------------------------------------- a run


@dataclasses.dataclass(frozen=True)
class ShardRun:
    """A goal-sharded training run.

    Attributes:
        out: the rule base's directory.
        n: number of blocks.
        params: CS-QL parameters.
        seed: the seed.
        trials: random training trials, over all shards.
        shards: the number of shards (see :func:`default_shards`).
        backend: where the shards run (workers, local or Ray): not part of the result.
        resume: continue the incomplete rule base at ``out``.

    """

    out: Path
    n: int
    params: CSQLParams
    seed: int
    trials: int
    shards: int
    backend: Backend = Backend()
    resume: bool = False


def manifest_for(run: ShardRun) -> dict:
    """The manifest of ``run`` before any shard: what determines the content, nothing of how it is computed."""
    count = len(BlocksWorld.of(run.n).states)
    if not 1 <= run.shards <= count:
        raise CsqlError(f"--shards must be 1..{count} (the goals) at {run.n} blocks, got {run.shards}")
    rules = [[r.condition, r.action] for r in r_classifiers(run.n)]
    return {"format": rs.FORMAT, "version": rs.VERSION, "method": "cs-ql", "blocks": run.n, "count": count,
            "seed": run.seed, "trials": run.trials, "shards": run.shards, "params": plain(run.params),
            "r_classifiers": rules, "complete": False, "files": [],
            "provenance": provenance(method="cs-ql", trials=run.trials, seed=run.seed, blocks=run.n,
                                     shards=run.shards, learner_params=run.params)}


def _resumable(run: ShardRun, fresh: dict) -> tuple[dict, set[int]]:
    """The manifest to continue and the shards already good (checked); refuses another run's directory."""
    old = rs.read_manifest(run.out)
    keys = ("method", "blocks", "count", "seed", "trials", "shards", "params", "r_classifiers")
    differ = [k for k in keys if old.get(k) != fresh[k]]
    if differ:
        raise CsqlError(f"--resume: {run.out} was trained with other {', '.join(differ)}; "
                        "give the same options or another --out")
    good = set()
    for entry in old["files"]:  # read_manifest checked each entry's shard, file name and SHA-256
        path = run.out / rs.shard_name(entry["shard"])
        if rs.is_own_file(path) and rs.file_sha256(path) == entry["sha256"]:
            good.add(entry["shard"])
    fresh["files"] = [e for e in old["files"] if e["shard"] in good]
    return fresh, good


def train_sharded(run: ShardRun, progress: bool = False,
                  on_shard: Callable[[int, ShardOutcome], None] | None = None) -> dict:
    """Train ``run``'s missing shards, writing each as it comes back; the run report.

    Raises:
        CsqlError: a refused resume, or shards that failed (the rule base stays incomplete:
            ``--resume`` retries them).
    """
    manifest = manifest_for(run)
    done: set[int] = set()
    rs.check_own_files(run.out)  # a link or folder named as one of our files: refused before any write
    previous = read_reports(run.out)[0]
    if run.resume:
        manifest, done = _resumable(run, manifest)
        manifest["complete"] = len(manifest["files"]) == run.shards
    else:
        _clear(run.out)
    created = not run.out.exists()
    run.out.mkdir(parents=True, exist_ok=True)
    rs.write_manifest(run.out, manifest)
    jobs = [ShardJob(run.n, run.params, run.seed, run.shards, k, run.trials) for k in range(run.shards)
            if k not in done]
    began, outcomes, failures = time.perf_counter(), {}, []
    shared = SharedModel(run.n, world_model(run.n))

    def save(i: int, outcome: ShardOutcome | TaskFailure) -> int:
        k = jobs[i].index
        if isinstance(outcome, TaskFailure):
            failures.append(f"shard {k}: {outcome.reason}")
            return k
        path = write_atomic(run.out / rs.shard_name(k), rs.shard_bytes(k, outcome.arrays), follow_links=False)
        lo, hi = rs.goal_range(manifest["count"], run.shards, k)
        manifest["files"] = sorted([*manifest["files"], {
            "shard": k, "file": path.name, "sha256": rs.file_sha256(path), "goals": [lo, hi],
            "q_classifiers": outcome.q_classifiers, "clock": outcome.arrays.clock}], key=lambda e: e["shard"])
        manifest["complete"] = len(manifest["files"]) == run.shards
        rs.write_manifest(run.out, manifest)
        outcomes[k] = outcome._replace(arrays=None)  # written: the arrays may go
        if on_shard is not None:
            on_shard(k, outcome)
        return k

    try:
        map_tasks(train_shard, jobs, run.backend, setup=install_model, setup_args=(shared,), progress=progress,
                  desc=f"shards ({run.n} blocks)", unit="shard", on_result=save)
    except CsqlError:  # refused before any shard (an unreachable Ray cluster): leave nothing behind
        if not run.resume and not outcomes:
            _clear(run.out)
            if created:
                run.out.rmdir()
        raise
    report = run_report(run, outcomes, time.perf_counter() - began, resumed=sorted(done))
    write_atomic(run.out / rs.REPORT, json.dumps({"format": "csql-sim shard run reports", "version": REPORT_VERSION,
                                                  "runs": [*previous, report]}, indent=1) + "\n", follow_links=False)
    if failures:
        raise CsqlError(f"{len(failures)} shard(s) failed ({failures[0]}); {run.out} is incomplete: "
                        "rerun with --resume")
    return report


def _clear(directory: Path) -> None:
    """Remove a previous sharded rule base from ``directory``: the manifest and the shard files it names only."""
    if not rs.is_sharded(directory):
        return
    old = rs.read_manifest(directory)  # a corrupt manifest is named, not silently replaced
    for entry in old["files"]:
        name = entry.get("file") if isinstance(entry, dict) else None
        path = directory / name if isinstance(name, str) and "/" not in name else None
        if path is not None and rs.is_own_file(path) and path.name.startswith("shard-"):
            path.unlink()
    (directory / rs.MANIFEST).unlink()


def run_report(run: ShardRun, outcomes: dict[int, ShardOutcome], wall: float, resumed: list[int]) -> dict:
    """How this run computed its shards: workers, backend, wall time, peak memory, optimal pairs."""
    rss_self = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * (1 if sys.platform == "darwin" else 1024)
    workers = worker_count(run.backend.workers, run.shards) if run.backend.kind == "processes" else None
    return {"format": "csql-sim shard run report", "version": REPORT_VERSION, "backend": run.backend.kind,
            "workers": workers, "address": run.backend.address, "wall_seconds": round(wall, 3),
            "shards_trained": sorted(outcomes), "shards_resumed": resumed,
            "peak_rss_bytes": {"driver": rss_self,
                               "worker_max": max((o.peak_rss for o in outcomes.values()), default=0)},
            "optimal_pairs": sum(o.optimal for o in outcomes.values()),
            "optimal_steps": sum(o.optimal_steps for o in outcomes.values()),
            "pairs": sum(o.pairs for o in outcomes.values()),
            "steps": sum(o.steps for o in outcomes.values()),
            "phases": {"trials": {"steps": sum(o.trial_steps for o in outcomes.values()),
                                  "optimal_pairs": sum(o.trials_optimal for o in outcomes.values()),
                                  "experienced_pairs_max": max((o.experienced_pairs for o in outcomes.values()),
                                                               default=0)},
                       "sweep": {"sweep": "value-iteration" if run.params.sweep else "none",
                                 "order": "backward breadth-first from each goal",
                                 "backups": sum(o.sweep_backups for o in outcomes.values()),
                                 "optimal_pairs": sum(o.optimal for o in outcomes.values())}},
            "cpu_seconds": round(sum(o.cpu_seconds for o in outcomes.values()), 1),
            "shard_seconds": {str(k): round(o.seconds, 3) for k, o in sorted(outcomes.items())}}


def read_reports(directory: Path) -> tuple[list, str | None]:
    """The run reports kept beside a rule base, and why the file was set aside if it cannot be read (else None).

    The reports are not part of the rule base: an unreadable file (corrupt, nested too
    deep) is replaced by the next run's report rather than stopping the run.
    """
    path = directory / rs.REPORT
    if not os.path.lexists(path):
        return [], None
    try:
        old = read_json_file(path, MAX_REPORT_BYTES, "run report")
    except CsqlError as exc:
        return [], str(exc)
    runs = old.get("runs") if isinstance(old, dict) else None
    return (runs, None) if isinstance(runs, list) else ([], f"{path} is not a list of run reports")
