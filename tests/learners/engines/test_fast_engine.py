import subprocess
import sys

import numpy as np
import pytest

from csql_sim.core.files.rulebase import dumps
from csql_sim.core.policies.rollout import check_pairs
from csql_sim.core.state.world import BlocksWorld
from csql_sim.learners.engines.fast_engine import FastCSQL, world_model
from csql_sim.learners.generalize.pruning import prune
from csql_sim.learners.paper.params import ParamsError
from csql_sim.learners.paper.trial import run_training
from csql_sim.learners.training.tabular import make_learner, train


@pytest.mark.parametrize("seed", [0, 1, 7])
def test_fast_and_reference_write_the_same_rule_file_n3(seed):
    fast = train("cs-ql", 2500, seed=seed, engine="fast")
    ref = train("cs-ql", 2500, seed=seed, engine="reference")
    assert dumps(fast) == dumps(ref)
    assert fast.meta["sweep_steps"] > 0


def test_same_curves_and_dyna_sweep_n3():
    over = {"sweep_backup_all": True, "sweep_greedy_tail": 2}
    assert dumps(train("cs-ql", 400, 3, params=over, engine="fast")) == dumps(
        train("cs-ql", 400, 3, params=over, engine="reference"))
    a, b = make_learner("cs-ql", seed=9, engine="fast"), make_learner("cs-ql", seed=9, engine="reference")
    assert a.train(600) == b.train(600) == run_training(make_learner("cs-ql", seed=9, engine="reference"), 600)
    assert a.t == b.t


def test_fast_and_reference_agree_on_n4_small():
    over = {"sweep": False}
    fast = train("cs-ql", 150, seed=2, n=4, params=over, engine="fast")
    ref = train("cs-ql", 150, seed=2, n=4, params=over, engine="reference")
    fields = [[(c.kind, c.condition, c.action, *((c.q, c.strength, c.age, c.error, c.born) if c.kind == "Q" else ()))
               for c in rb.classifiers] for rb in (fast, ref)]
    assert fields[0] == fields[1] and len(fields[0]) > 1000


def test_world_model_from_the_r_classifiers_equals_the_world():
    for n in (3, 4):
        model, world = world_model(n), BlocksWorld.of(n)
        for s in range(len(world.states)):
            acts = model.action[model.lo[s] : model.lo[s + 1]].tolist()
            assert acts == list(world.legal[s])
            assert model.nxt[model.lo[s] : model.lo[s + 1]].tolist() == [world.next_state[s][a] for a in acts]


def test_engine_choice():
    assert isinstance(make_learner("cs-ql", 4, engine=None), FastCSQL)
    assert not isinstance(make_learner("cs-ql", 3, engine="reference"), FastCSQL)
    with pytest.raises(ParamsError):
        make_learner("cs-bb-bz", 3, engine="fast")
    with pytest.raises(ParamsError):
        make_learner("cs-ql", 3, engine="turbo")


@pytest.mark.slow
def test_n4_defaults_prune_to_one_optimal_classifier_per_pair():
    rb = train("cs-ql", n=4)  # the defaults for n = 4
    pruned = prune(rb, 0.1)
    q = [c for c in pruned.classifiers if c.kind == "Q"]
    assert len(q) == 15_500 == len({c.condition for c in q})
    from csql_sim.core.policies.greedy_table import GreedyTable

    results = list(check_pairs(GreedyTable.from_rulebase(pruned), 4, "all"))
    assert len(results) == 15_500 and all(r.optimal for r in results)


@pytest.mark.slow
def test_cli_train_n4_then_plan_all_pairs(tmp_path):
    out = tmp_path / "r4.npz"
    cli = [sys.executable, "-m", "csql_sim"]
    subprocess.run([*cli, "train", "--blocks", "4", "--out", str(out), "--no-progress"], check=True)
    done = subprocess.run([*cli, "plan", "--rules", str(out), "--pairs", "all"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("pairs: 15500  covered: 15500  optimal: 15500")
    assert np.load(out)["kind"].shape[0] > 15_500
