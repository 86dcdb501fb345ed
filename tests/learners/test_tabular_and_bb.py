import pytest

from csql_sim.learners import count_q, make_learner, train
from csql_sim.world import BlocksWorld


def test_lt_ql_row_covers_all_18_actions_and_illegal_keeps_state():
    learner = make_learner("lt-ql", seed=0)
    world = BlocksWorld.of(3)
    row = learner.node(0, 5)
    assert len(row.q) == 18
    for a in range(18):
        nxt = learner.successor(row, a)
        want = world.next_state[0][a]
        if want < 0:
            assert nxt is row
        elif want == 5:
            assert nxt is None
        else:
            assert (nxt.state, nxt.goal) == (want, 5)


def test_lt_ql_learns_the_test_task_and_exports_its_table():
    learner = make_learner("lt-ql", seed=0)
    curve = learner.run(2500)
    assert curve.steps[0] > 200 and curve.steps[-1] == 8
    start, goal = learner.test_task()
    assert learner.run_trial(start, goal, 0.0, cap=50).steps == 8
    rb = learner.rulebase()
    assert count_q(rb) == 18 * len(learner._rows)
    assert not any(c.kind == "R" for c in rb.classifiers)


def test_bucket_brigade_passes_bids_back_and_pays_at_the_goal():
    learner = make_learner("cs-bb-bz", seed=0, params={"bid": 0.2, "s0": 0.5})
    first = learner.node(0, 1)
    i = next(k for k in range(len(first.qs)) if learner.successor(first, k) is not None)
    second = learner.successor(first, i)
    j = 0
    learner.begin_trial()
    learner.update(first, i, second, 1)
    assert first.qs[i].strength == pytest.approx(0.4)  # paid its bid to nobody (trial start)
    learner.update(second, j, None, 2)  # pretend it reached the goal
    assert second.qs[j].strength == pytest.approx(0.5 - 0.1 + 0.2)
    assert first.qs[i].strength == pytest.approx(0.4 + 0.1)


def test_tax_charges_unselected_candidates():
    learner = make_learner("cs-bb-rw", seed=0, params={"tax": 0.1, "s0": 0.5})
    node = learner.node(0, 1)
    learner.begin_trial()
    learner.update(node, 0, learner.successor(node, 0), 1)
    assert [c.strength for c in node.qs[1:]] == pytest.approx([0.45] * (len(node.qs) - 1))


@pytest.mark.parametrize("method", ["cs-bb-bz", "cs-bb-rw"])
def test_bucket_brigade_rule_files_are_deterministic_and_q_is_strength(method):
    a, b = train(method, 300, seed=3), train(method, 300, seed=3)
    qa = [(c.condition, c.action, c.strength, c.q) for c in a.classifiers if c.kind == "Q"]
    assert qa == [(c.condition, c.action, c.strength, c.q) for c in b.classifiers if c.kind == "Q"]
    assert all(s == q for _, _, s, q in qa)
