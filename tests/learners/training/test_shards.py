"""Goal-sharded training: byte-identical across workers and backends, resumable, checked, read lazily."""

import hashlib
import importlib.util

import numpy as np
import pytest

from csql_sim.core.files import rulebase_shards as rs
from csql_sim.core.files.rulebase_yaml import RuleBaseError
from csql_sim.core.model.search import true_distances
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.policies.rollout import check_pairs
from csql_sim.core.policies.sharded_policy import ShardedPolicy
from csql_sim.core.state.world import BlocksWorld
from csql_sim.infra.backends import Backend
from csql_sim.learners.paper.params import defaults_for_blocks
from csql_sim.learners.training.shards import ShardRun, shard_trials, train_sharded

needs_ray = pytest.mark.skipif(importlib.util.find_spec("ray") is None, reason="the ray extra is not installed")
N, SHARDS, TRIALS = 4, 5, 3000


def run(out, workers=1, kind="processes", resume=False, seed=0):
    return ShardRun(out, N, defaults_for_blocks("cs-ql", N), seed, TRIALS, SHARDS, Backend(kind, workers), resume)


def contents(directory):
    """The rule base's files (the run report is not part of it) and their SHA-256."""
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(directory.iterdir())
            if p.name != rs.REPORT}


@pytest.fixture(scope="module")
def one_worker(tmp_path_factory):
    out = tmp_path_factory.mktemp("shards") / "rules4"
    report = train_sharded(run(out, workers=1))
    return out, report


def test_every_pair_optimal_and_the_count_is_the_tools_own(one_worker):
    out, report = one_worker
    count = len(BlocksWorld.of(N).states)
    assert report["pairs"] == count * (count - 1) == 15_500
    assert report["optimal_pairs"] == report["pairs"]
    policy = load_policy(out, N)
    assert isinstance(policy, ShardedPolicy)
    results = list(check_pairs(policy, N, 400, seed=3))
    assert all(r.optimal for r in results)  # rolled out in the true world, against BFS
    s, g = 7, 101
    a = policy.action_index(s, g)
    nxt = BlocksWorld.of(N).next_state[s][a]
    assert true_distances(N, g)[nxt] == true_distances(N, g)[s] - 1


def test_the_run_report_puts_each_measure_in_its_field(one_worker):
    """Counts are counts of pairs or steps, times are seconds of this run, the peak is a process's memory."""
    _, report = one_worker
    pairs, trials = report["pairs"], report["phases"]["trials"]
    assert isinstance(trials["optimal_pairs"], int) and 0 <= trials["optimal_pairs"] <= pairs
    assert report["optimal_pairs"] <= report["optimal_steps"] <= pairs  # every first step of an optimal pair is
    assert isinstance(trials["steps"], int) and 0 < trials["steps"] <= report["steps"]
    assert 0 < trials["experienced_pairs_max"] <= pairs
    assert all(0 < s <= report["wall_seconds"] for s in report["shard_seconds"].values())  # one worker: in turn
    assert report["peak_rss_bytes"]["worker_max"] >= 1 << 20  # an interpreter's resident memory, in bytes


def test_two_workers_write_the_same_bytes(one_worker, tmp_path):
    out, _ = one_worker
    other = tmp_path / "two"
    train_sharded(run(other, workers=2))
    assert contents(other) == contents(out)
    assert len(contents(out)) == SHARDS + 1


def test_shares_of_trials_and_goals_cover_everything():
    assert sum(shard_trials(TRIALS, SHARDS, k) for k in range(SHARDS)) == TRIALS
    ranges = [rs.goal_range(125, SHARDS, k) for k in range(SHARDS)]
    assert ranges[0][0] == 0 and ranges[-1][1] == 125
    assert all(a[1] == b[0] for a, b in zip(ranges, ranges[1:], strict=False))


def test_an_interrupted_run_is_refused_then_resumed_to_the_same_file(one_worker, tmp_path):
    out, _ = one_worker
    stopped = tmp_path / "stopped"

    def stop_after_two(k, outcome):
        if len(list(stopped.glob("shard-*.bin"))) == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        train_sharded(run(stopped), on_shard=stop_after_two)
    manifest = rs.read_manifest(stopped)
    assert manifest["complete"] is False and len(manifest["files"]) == 2
    with pytest.raises(RuleBaseError, match="incomplete"):
        load_policy(stopped, N)
    report = train_sharded(run(stopped, resume=True))
    assert report["shards_resumed"] == [0, 1] and report["shards_trained"] == [2, 3, 4]
    assert contents(stopped) == contents(out)


def test_resume_refuses_other_options(one_worker, tmp_path):
    out, _ = one_worker
    copy = tmp_path / "copy"
    copy.mkdir()
    for p in out.iterdir():
        (copy / p.name).write_bytes(p.read_bytes())
    with pytest.raises(Exception, match="other seed"):
        train_sharded(run(copy, resume=True, seed=5))


def test_a_corrupt_shard_is_named_not_used(one_worker, tmp_path):
    out, _ = one_worker
    copy = tmp_path / "corrupt"
    copy.mkdir()
    for p in out.iterdir():
        (copy / p.name).write_bytes(p.read_bytes())
    shard = copy / rs.shard_name(2)
    data = bytearray(shard.read_bytes())
    data[-9] ^= 0xFF
    shard.write_bytes(bytes(data))
    policy = load_policy(copy, N)
    lo, _ = rs.goal_range(125, SHARDS, 2)
    assert policy.action_index(0, lo - 1) >= 0  # another shard is fine
    with pytest.raises(RuleBaseError, match="shard 2 .*corrupt"):
        policy.action_index(0, lo)


@pytest.mark.parametrize("k", [2, 20])
def test_sampling_k_pairs_opens_at_most_k_shards_and_hashes_each_once(one_worker, monkeypatch, k):
    out, _ = one_worker
    opened, hashed = [], []
    real = rs.read_shard

    def spy(path, index, sha, nodes=None):
        opened.append(index)
        if sha is not None:
            hashed.append(index)
        return real(path, index, sha, nodes)

    monkeypatch.setattr(rs, "read_shard", spy)
    policy = load_policy(out, N)
    results = list(check_pairs(policy, N, k, seed=11))
    assert len(results) == k and 0 < len(set(opened)) <= len({r.goal for r in results}) <= k
    assert len(hashed) == len(set(hashed))  # a shard re-opened after the cache let it go is not hashed again


def test_goal_columns_match_the_lazy_policy(one_worker):
    out, _ = one_worker
    policy = load_policy(out, N)
    goals = (0, 30, 124)
    columns = policy.columns(goals)
    expected = np.array([[policy.action_index(s, g) for s in range(125)] for g in goals])
    assert (columns == expected).all()
    assert (columns[np.arange(3), list(goals)] == -1).all()  # no classifier at the goal itself


@pytest.mark.slow
@needs_ray
def test_ray_writes_the_same_bytes(one_worker, tmp_path):
    out, _ = one_worker
    other = tmp_path / "ray"
    train_sharded(run(other, workers=2, kind="ray"))
    assert contents(other) == contents(out)
