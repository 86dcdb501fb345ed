"""LT-QL's array engine follows its reference engine step for step: the same rule file, byte for byte."""

import numpy as np
import pytest

from csql_sim.core.files.rulebase import load
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.infra.errors import CsqlError
from csql_sim.learners.engines import lt_fast
from csql_sim.learners.engines.lt_fast import FastTabularQ
from csql_sim.learners.paper.learner import Learner
from csql_sim.learners.paper.lt_ql import TabularQ
from csql_sim.learners.paper.params import ParamsError, TabularParams
from csql_sim.learners.training.tabular import make_learner

META = {"method": "lt-ql", "note": "test"}


def pair(n=3, seed=0, **params):
    fast = make_learner("lt-ql", n, params or None, seed=seed, engine="fast")
    ref = make_learner("lt-ql", n, params or None, seed=seed, engine="reference")
    assert isinstance(fast, FastTabularQ) and isinstance(ref, TabularQ)
    return fast, ref


def fields(learner):
    return [(c.condition, c.action, c.q, c.strength, c.age, c.error, c.last_active, c.born)
            for c in learner.rulebase(META).classifiers]


def assert_same(fast, ref, tmp_path, yaml=False):
    assert fast.t == ref.t and fast.counts() == ref.counts()
    assert fields(fast) == fields(ref)
    assert fast.file_bytes(tmp_path / "r.npz", META) == ref.file_bytes(tmp_path / "r.npz", META)
    if yaml:
        assert fast.file_bytes(tmp_path / "r.yaml", META) == ref.file_bytes(tmp_path / "r.yaml", META)
    assert np.array_equal(fast.greedy_table().best, ref.greedy_table().best)


@pytest.mark.parametrize("seed", [0, 1, 7])
def test_same_trajectory_and_rule_file_as_the_reference_n3(seed, tmp_path):
    fast, ref = pair(seed=seed)
    assert fast.train(200) == ref.train(200)
    assert ref.counts()[1] > 6000  # most of the 462 pairs have a row of 18 entries
    assert_same(fast, ref, tmp_path)


def test_same_yaml_bytes_n3(tmp_path):
    fast, ref = pair(seed=3, step_cap=30)
    assert fast.train(25) == ref.train(25)
    assert 0 < fast.counts()[1] < 22 * 21 * 18
    assert_same(fast, ref, tmp_path, yaml=True)


def test_same_rule_file_n4_while_the_table_grows(tmp_path, monkeypatch):
    monkeypatch.setattr(lt_fast, "INITIAL_ROWS", 5)
    grows: list[int] = []
    grow = FastTabularQ._grow
    monkeypatch.setattr(FastTabularQ, "_grow", lambda self, cap: grows.append(self.capacity) or grow(self, cap))
    fast, ref = pair(n=4, seed=2, step_cap=150)
    assert fast.capacity == 5
    assert fast.train(40) == ref.train(40)
    assert len(grows) >= 2 and grows[0] == 5 and fast.capacity >= fast.rows > 150
    assert_same(fast, ref, tmp_path)


def test_pauses_and_a_second_train_call_do_not_change_the_trajectory(tmp_path, monkeypatch):
    whole, ref = pair(seed=5)
    whole.train(150)
    whole.train(70)
    ref.train(150)
    ref.train(70)
    calls = []
    kernel = lt_fast.lk.run_trials  # the compiled function (the module attribute is looked up lazily)
    monkeypatch.setattr(lt_fast, "STEPS_PER_CALL", 7)
    monkeypatch.setattr(lt_fast.lk, "run_trials", lambda *args: calls.append(1) or kernel(*args), raising=False)
    cut = make_learner("lt-ql", 3, seed=5, engine="fast")
    seen: list[int] = []
    cut.train(150, on_trial=seen.append)
    cut.train(70)
    assert seen == list(range(150)) and len(calls) > 200  # it paused, between trials, many times
    assert_same(cut, ref, tmp_path)
    assert cut.file_bytes(tmp_path / "r.npz", META) == whole.file_bytes(tmp_path / "r.npz", META)


def test_the_contract(tmp_path):
    learner = make_learner("lt-ql", 3, {"step_cap": 5}, seed=4, engine=None)  # a small table: YAML is slow
    assert isinstance(learner, Learner) and (learner.method, learner.engine) == ("lt-ql", "fast")
    assert learner.t == 0 and learner.counts() == (0, 0) and learner.rulebase().classifiers == []
    assert (learner.greedy_table().best == -1).all()
    curve = learner.train(40, test_every=20)
    assert curve.trials == (0, 20, 40) and all(s > 0 for s in curve.steps)
    assert learner.t >= sum(curve.steps) + 40
    before = learner.t
    assert learner.max_sweep_passes == 0 and learner.sweep() == 0 and learner.t == before
    for suffix in (".npz", ".yaml"):
        path = learner.write(tmp_path / f"rules{suffix}", META)
        back = load(path)
        assert back.meta == META and len(back.classifiers) == learner.counts()[1]
        assert np.array_equal(GreedyTable.from_rulebase(back).best, learner.greedy_table().best)


def test_greedy_table_is_the_rows_first_largest_q():
    learner = make_learner("lt-ql", 3, seed=8, engine="fast")
    learner.train(40)
    k, a, count = learner.kernel, learner.actions, learner.count
    best = learner.greedy_table().best
    for j in range(learner.rows):
        q = k.q[j * a : (j + 1) * a].tolist()
        assert best[k.row_state[j] * count + k.row_goal[j]] == q.index(max(q))
    assert (best >= 0).sum() == learner.rows


def test_engine_choice():
    assert isinstance(make_learner("lt-ql", 4, engine=None), FastTabularQ)
    assert isinstance(make_learner("lt-ql", 3, engine="reference"), TabularQ)
    with pytest.raises(ParamsError):
        make_learner("cs-bb-bz", 3, engine="fast")
    with pytest.raises(CsqlError):  # n = 6 would need up to 86 GB
        FastTabularQ(6, TabularParams(), np.random.default_rng(0))
