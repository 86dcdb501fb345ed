"""Every learner make_learner returns keeps the one Learner contract, whichever engine runs it."""

import pathlib

import numpy as np
import pytest

from csql_sim.core.files.rulebase import dumps, load
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.learners.paper.learner import Curve, Learner
from csql_sim.learners.training.tabular import make_learner, train_learner

KINDS = [("lt-ql", "reference"), ("lt-ql", "fast"), ("cs-ql", "reference"), ("cs-ql", "fast"),
         ("cs-bb-bz", "reference"), ("cs-bb-rw", "reference")]
TRIALS = 120


def trained(method: str, engine: str, n: int = 3, **params) -> Learner:
    learner = make_learner(method, n, params or None, seed=4, engine=engine)
    learner.train(TRIALS)
    return learner


@pytest.mark.parametrize(("method", "engine"), KINDS)
def test_train_reports_every_trial_and_returns_the_test_task_curve(method, engine):
    learner = make_learner(method, 3, seed=4, engine=engine)
    assert isinstance(learner, Learner)
    assert (learner.method, learner.engine) == (method, engine)
    seen: list[int] = []
    curve = learner.train(TRIALS, on_trial=seen.append)
    assert seen == list(range(TRIALS))
    assert isinstance(curve, Curve) and curve.trials == (0, 50, 100)
    assert len(curve.steps) == len(curve.values) == 3 and all(s > 0 for s in curve.steps)
    assert learner.t >= sum(curve.steps) + TRIALS


@pytest.mark.parametrize(("method", "engine"), KINDS)
def test_greedy_table_is_the_rule_base_policy(method, engine):
    learner = trained(method, engine)
    table = learner.greedy_table()
    count = len(learner.world.states)
    assert isinstance(table, GreedyTable) and table.n == 3
    assert table.best.shape == (count * count,) and table.best.dtype == np.int8
    assert (table.best >= 0).any()
    assert np.array_equal(table.best, GreedyTable.from_rulebase(learner.rulebase()).best)


@pytest.mark.parametrize(("method", "engine"), KINDS)
@pytest.mark.parametrize("suffix", [".yaml", ".npz"])
def test_write_reads_back_as_the_rule_base(method, engine, suffix, tmp_path):
    learner = trained(method, engine)
    meta = {"method": method, "trials": TRIALS}
    path = learner.write(tmp_path / f"rules{suffix}", meta)
    content = learner.file_bytes(path, meta)
    assert path.read_bytes() == (content.encode() if isinstance(content, str) else content)
    back = load(path)
    assert dumps(back) == dumps(learner.rulebase(meta))
    r = sum(c.kind == "R" for c in back.classifiers)
    assert learner.counts() == (r, len(back.classifiers) - r)


@pytest.mark.parametrize(("method", "engine"), KINDS)
def test_sweep_only_where_the_method_has_one(method, engine):
    learner = trained(method, engine)
    before = learner.t
    swept = learner.sweep()
    if method == "cs-ql":
        assert learner.max_sweep_passes > 0 and swept > 0 and learner.t > before + swept  # + the greedy test task
    else:
        assert learner.max_sweep_passes == 0 and swept == 0 and learner.t == before
    off = trained("cs-ql", "reference", sweep=False)
    assert off.max_sweep_passes == 0 and off.sweep() == 0


def test_both_cs_ql_engines_keep_the_contract_identically(tmp_path):
    fast, ref = trained("cs-ql", "fast"), trained("cs-ql", "reference")
    assert fast.sweep() == ref.sweep() and fast.t == ref.t
    assert np.array_equal(fast.greedy_table().best, ref.greedy_table().best)
    assert fast.counts() == ref.counts()
    for suffix in (".yaml", ".npz"):
        assert fast.file_bytes(tmp_path / f"r{suffix}", {}) == ref.file_bytes(tmp_path / f"r{suffix}", {})


def test_train_learner_with_progress_bars_runs_the_sweep(capsys):
    learner, meta = train_learner("cs-ql", 60, seed=1, progress=True, engine="fast")
    assert meta["sweep_steps"] > 0 and meta["steps"] == learner.t
    _, meta_bb = train_learner("cs-bb-bz", 60, seed=1, progress=True)
    assert meta_bb["sweep_steps"] == 0


def test_no_caller_outside_the_learners_package_names_an_engine_class():
    root = pathlib.Path(__file__).resolve().parents[3] / "csql_sim"
    offenders = [str(p.relative_to(root)) for p in root.rglob("*.py")
                 if "learners" not in p.relative_to(root).parts
                 and any(name in p.read_text() for name in ("FastCSQL", "fast_engine"))]
    assert offenders == []
