from collections import deque

import pytest

from csql_sim.core.model.search import BfsPolicy, bfs_plan, distance
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import BlocksWorld, legal_actions, successor


def _forward_bfs(start, goal):
    frontier, seen = deque([(start, 0)]), {start}
    while frontier:
        s, d = frontier.popleft()
        if s == goal:
            return d
        for a in legal_actions(s):
            t = successor(s, a)
            if t not in seen:
                seen.add(t)
                frontier.append((t, d + 1))
    raise AssertionError("unreachable")


def test_mean_optimal_length_over_462_pairs():
    states = BlocksWorld.of(3).states
    lengths = [distance(s, g) for s in states for g in states if s != g]
    assert len(lengths) == 462
    assert sum(lengths) / 462 == pytest.approx(4.428571, abs=1e-6)
    assert max(lengths) == 8
    longest = [(s, g) for s in states for g in states if distance(s, g) == 8]
    assert (parse_config("CBA"), parse_config("BAC")) in longest


def test_test_task_plan_is_the_papers():
    plan = bfs_plan(parse_config("CBA"), parse_config("BAC"))
    assert [a.name() for a in plan] == [
        "unstack(A,B)", "putdown(A)", "unstack(B,C)", "putdown(B)",
        "pickup(A)", "stack(A,B)", "pickup(C)", "stack(C,A)",
    ]


@pytest.mark.parametrize("n", [3, 4])
def test_plans_are_valid_and_optimal(n):
    states = BlocksWorld.of(n).states
    pairs = [(s, g) for s in states[::3] for g in states[::5] if s != g]
    for s, g in pairs:
        plan = bfs_plan(s, g)
        state = s
        for a in plan:
            state = successor(state, a)
        assert state == g
        assert len(plan) == distance(s, g) == _forward_bfs(s, g)


def test_bfs_policy():
    policy = BfsPolicy()
    goal = parse_config("BAC")
    assert policy.act(goal, goal) is None
    assert policy.act(parse_config("CBA"), goal).name() == "unstack(A,B)"


def test_bfs_on_the_world_model_equals_bfs_on_the_world():
    from csql_sim.core.model.world_model import WorldModel
    from csql_sim.core.policies.rollout import check_all_pairs

    results = check_all_pairs(BfsPolicy(WorldModel.for_blocks(3)), 3)
    assert len(results) == 462 and all(r.optimal for r in results)


def test_bfs_on_a_world_model_that_forbids_pickups_finds_no_plan():
    from csql_sim.core.classifiers.r_classifier import PreconditionRule, generate_rules
    from csql_sim.core.model.search import NoPlanError
    from csql_sim.core.model.world_model import WorldModel

    rules = [r for r in generate_rules(3) if not (isinstance(r, PreconditionRule) and r.action[8:12] == "1000"
                                                  and r.action[13] == "t")]
    policy = BfsPolicy(WorldModel(rules, 3))
    with pytest.raises(NoPlanError):
        policy.act(parse_config("A,B,C"), parse_config("CBA"))
    # unstacking is still allowed, so taking a tower apart still has a plan
    assert policy.act(parse_config("CBA"), parse_config("A,B,C")) is not None
