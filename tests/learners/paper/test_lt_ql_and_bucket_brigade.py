import pytest

from csql_sim.core.model.task import test_task
from csql_sim.core.state.message import format_state_message
from csql_sim.core.state.world import BlocksWorld
from csql_sim.learners.generalize.pruning import count_q
from csql_sim.learners.paper.learner import Transition
from csql_sim.learners.paper.trial import run_training, run_trial
from csql_sim.learners.training.tabular import make_learner, train


def test_lt_ql_model_covers_all_18_actions_and_illegal_keeps_state():
    learner = make_learner("lt-ql", seed=0)
    world = BlocksWorld.of(3)
    message = format_state_message(world.states[0], 5)
    assert len(learner.row(message).q) == 18
    for a in range(18):
        want = world.next_state[0][a]
        assert learner.model.step(message, a) == format_state_message(world.states[want if want >= 0 else 0], 5)


def test_lt_ql_learns_the_test_task_and_exports_its_table():
    learner = make_learner("lt-ql", seed=0)
    curve = run_training(learner, 2500)
    assert curve.steps[0] > 200 and curve.steps[-1] == 8
    task = test_task(3)
    start, goal = learner.world.state_index(task.start), learner.world.state_index(task.goal)
    assert run_trial(learner, start, goal, 0.0, cap=50).steps == 8
    rb = learner.rulebase()
    assert count_q(rb) == 18 * len(learner._rows)
    assert not any(c.kind == "R" for c in rb.classifiers)


def _two_steps(learner):
    """A first message with a candidate that does not end the episode, and its successor."""
    world = learner.world
    message = format_state_message(world.states[0], 1)
    first = learner.block.post(message)
    i = next(k for k in range(len(first.candidates))
             if learner.model.step(message, first.actions[k]) != format_state_message(world.states[1], 1))
    return message, first, i


def test_bucket_brigade_passes_bids_back_and_pays_at_the_goal():
    learner = make_learner("cs-bb-bz", seed=0, params={"bid": 0.2, "s0": 0.5})
    message, first, i = _two_steps(learner)
    nxt = learner.model.step(message, first.actions[i])
    learner.begin_episode()
    learner.act(message, 1.0)
    learner.learn(Transition(message, first.actions[i], nxt, False))
    assert first.candidates[i].strength == pytest.approx(0.4)  # paid its bid to nobody (episode start)
    second = learner.block.post(nxt)
    after = learner.model.step(nxt, second.actions[0])
    learner.learn(Transition(nxt, second.actions[0], after, True))  # pretend it reached the goal
    assert second.candidates[0].strength == pytest.approx(0.5 - 0.1 + 0.2)
    assert first.candidates[i].strength == pytest.approx(0.4 + 0.1)


def test_tax_charges_unselected_candidates():
    learner = make_learner("cs-bb-rw", seed=0, params={"tax": 0.1, "s0": 0.5})
    message, first, i = _two_steps(learner)
    learner.begin_episode()
    learner.learn(Transition(message, first.actions[i], learner.model.step(message, first.actions[i]), False))
    others = [c.strength for k, c in enumerate(first.candidates) if k != i]
    assert others == pytest.approx([0.45] * (len(first.candidates) - 1))


@pytest.mark.parametrize("method", ["cs-bb-bz", "cs-bb-rw"])
def test_bucket_brigade_rule_files_are_deterministic_and_plans_follow_strength(method):
    a, b = train(method, 300, seed=3), train(method, 300, seed=3)
    qa = [(c.condition, c.action, c.strength, c.q) for c in a.classifiers if c.kind == "Q"]
    assert qa == [(c.condition, c.action, c.strength, c.q) for c in b.classifiers if c.kind == "Q"]
    assert a.meta["value"] == "strength"
    assert all(q == 0.0 for _, _, _, q in qa)  # the bucket brigade learns strengths only
