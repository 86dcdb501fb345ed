import numpy as np
import pytest

from csql_sim.core.files.rulebase import dumps
from csql_sim.core.policies.policy import QPolicy
from csql_sim.core.policies.rollout import check_all_pairs
from csql_sim.core.state.message import format_state_message, parse_state_message
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import BlocksWorld
from csql_sim.learners.generalize.pruning import count_q, figure6_table, greedy_path, prune
from csql_sim.learners.paper.cs_ql import CSQL
from csql_sim.learners.paper.learner import Transition
from csql_sim.learners.paper.trial import run_training, run_trial
from csql_sim.learners.training.tabular import make_learner, train


def all_optimal(rb) -> int:
    return sum(r.optimal for r in check_all_pairs(QPolicy.from_rulebase(rb), rb.blocks))


@pytest.fixture(scope="module")
def trained():
    return train("cs-ql", 2500, seed=0)


def test_cs_ql_2500_trials_optimal_for_all_462_pairs(trained):
    assert count_q(trained) == 882  # 22 goals x 42 legal pairs - 42 in the goal state
    assert sum(c.kind == "R" for c in trained.classifiers) == 36
    assert all_optimal(trained) == 462


def test_pruning_leaves_exactly_one_optimal_classifier_per_pair(trained):
    pruned = prune(trained, 0.1)
    assert count_q(pruned) == 462
    assert sum(c.kind == "R" for c in pruned.classifiers) == 36
    conditions = {c.condition for c in pruned.classifiers if c.kind == "Q"}
    assert len(conditions) == 462
    assert all_optimal(pruned) == 462


def test_paper_faithful_variant_prunes_some_needed_classifiers():
    rb = train("cs-ql", 2500, seed=0, params={"sweep": False})
    assert all_optimal(rb) == 462
    kept = count_q(prune(rb, 0.1))
    assert 400 < kept < 462  # the paper got 446: rarely visited pairs decay below 0.1


def test_same_seed_same_rule_file_different_seed_differs(trained):
    assert dumps(train("cs-ql", 2500, seed=0)) == dumps(trained)
    assert dumps(train("cs-ql", 300, seed=1)) != dumps(train("cs-ql", 300, seed=2))


def test_world_model_predictions_equal_the_world():
    learner = make_learner("cs-ql", seed=3)
    run_training(learner, 200)
    world = BlocksWorld.of(3)
    checked = 0
    for c in learner.classifiers.q_classifiers:
        parsed = parse_state_message(c.condition, 3)
        s = world.state_index(parsed.state)
        a = int(c.action[1], 36) - 1
        assert a in world.legal[s]
        nxt = learner.model.step(c.condition, a)
        assert nxt == format_state_message(world.states[world.next_state[s][a]], parsed.goal)
        checked += 1
    assert checked > 100


def test_classifiers_only_created_by_cover_and_never_in_goal_state():
    learner = make_learner("cs-ql", seed=0)
    run_trial(learner, 0, 12, 0.5)
    qs = learner.classifiers.q_classifiers
    assert qs and all(c.condition != format_state_message(BlocksWorld.of(3).states[12], 12) for c in qs)
    legal = BlocksWorld.of(3).legal
    by_state = {c.condition for c in qs}
    assert len(qs) == sum(len(legal[BlocksWorld.of(3).state_index(parse_state_message(m, 3).state)]) for m in by_state)


def test_error_grows_lazily_and_resets_on_activation():
    learner = make_learner("cs-ql", seed=0)
    assert isinstance(learner, CSQL)
    world = BlocksWorld.of(3)
    cba, bac = world.state_index(parse_config("CBA")), world.state_index(parse_config("BAC"))
    start = format_state_message(world.states[cba], bac)  # one legal action: unstack(A,B)
    run_trial(learner, cba, bac, 0.5, cap=1)
    c = learner.classifiers.q_for(start)["A10000001000ab00"]
    assert c.last_active == learner.t
    before = learner.error(c)
    learner.t += 1000
    assert learner.error(c) == pytest.approx(before + 0.2)
    learner.t -= 1000
    # activating it again resets |epsilon| to the new prediction error, with no growth
    run_trial(learner, cba, bac, 0.5, cap=1)
    assert c.last_active == learner.t and learner.error(c) == pytest.approx(c.error)
    assert learner.error(c) < before + 0.2


def test_q_update_follows_eq1_and_eq2():
    learner = make_learner("cs-ql", seed=0, params={"eta": 0.5})
    message = "S0111000ttt00001"  # all on the table, goal index 1
    action = learner.act(message, 1.0)
    nxt = learner.model.step(message, action)
    following = learner.block.post(nxt)
    for d in following.candidates:
        d.q = 0.4
    c = learner.block.post(message).candidates[learner.block.post(message).index_of(action)]
    c.q = 0.1
    learner.learn(Transition(message, action, nxt, False))
    target = 0.95 * 0.4
    assert c.q == pytest.approx(0.1 + 0.5 * (target - 0.1))
    assert c.error == pytest.approx(abs(target - 0.1)) and c.last_active == learner.t == 1


def test_figure6_table_for_the_test_task(trained):
    start, goal = parse_config("CBA"), parse_config("BAC")
    path = greedy_path(trained, start, goal)
    assert len(path) == 8
    assert [c.q for c in path] == pytest.approx([0.95**k for k in range(7, -1, -1)], abs=1e-3)
    assert path[0].condition == "S0100000bct0000C" and path[-1].action == "AH0000000100ca00"
    table = figure6_table(trained, start, goal).splitlines()
    assert table[0].split() == ["T", "Condition", "Action", "Strength", "Q-value", "Age", "PredErr"]
    assert len(table) == 9 and table[-1].split()[-1] == "0.000000"
    assert len(figure6_table(trained).splitlines()) == 883
    # the notation strings env.reset accepts (and a state message) give the same table
    assert figure6_table(trained, "CBA", "bac") == figure6_table(trained, start, goal)
    assert figure6_table(trained, "S0100000bct0000C", "BAC") == figure6_table(trained, start, goal)


def test_generator_is_the_only_randomness():
    a = run_training(make_learner("cs-ql", rng=np.random.default_rng(5)), 100)
    b = run_training(make_learner("cs-ql", rng=np.random.default_rng(5)), 100)
    assert a == b


def test_cs_ql_takes_the_same_steps_as_the_plain_tabular_learner():
    from csql_sim.jobs.bench import plain_q_learning

    learner = make_learner("cs-ql", seed=4)
    run_training(learner, 600)
    assert plain_q_learning(600, 4) == learner.t
