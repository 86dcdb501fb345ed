"""Physical episodes on a sharded rule base: the workers get the sampled goals' columns only."""

import pytest

from csql_sim.core.policies.loader import load_policy
from csql_sim.jobs.evaluate import PolicyData, evaluate
from csql_sim.learners.paper.params import defaults_for_blocks
from csql_sim.learners.training.shards import ShardRun, train_sharded


@pytest.fixture(scope="module")
def sharded4(tmp_path_factory):
    out = tmp_path_factory.mktemp("ev") / "rules4"
    train_sharded(ShardRun(out, 4, defaults_for_blocks("cs-ql", 4), 0, 1000, 4))
    return out


def test_policy_data_ships_the_goals_columns_only(sharded4):
    data = PolicyData.read(sharded4, 4, goals=(5, 99, 5))
    assert data.goals == (5, 99) and len(data.best) == 2 * 125 * 2  # int16 columns of two goals
    shipped, lazy = data.policy(), load_policy(sharded4, 4)
    assert all(shipped.action_index(s, g) == lazy.action_index(s, g) for g in (5, 99) for s in range(125))
    assert shipped.action_index(3, 6) == -1  # a goal that was not shipped


@pytest.mark.slow
def test_evaluate_reaches_the_goals_on_the_arm(sharded4):
    report = evaluate(n=4, pairs=2, rules=str(sharded4), workers=1, progress=False, seed=4)
    assert report.episodes == 2 and report.successes == 2
