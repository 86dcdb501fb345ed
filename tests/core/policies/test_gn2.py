import numpy as np
import pytest

from csql_sim.core.measure.bounds import lower_bound
from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model.search import distance_matrix
from csql_sim.core.model.task_draws import draw_task
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.gn2 import Gn2Policy, enables_constructive, gn2_block
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.policies.rollout import check_pairs
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.relation_tracker import RelationTracker
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.core.state.world import all_states, successor


def test_a_hand_worked_deadlock_is_broken_where_it_enables_a_constructive_move():
    start, goal = parse_config("AB,CD"), parse_config("AD,CB")  # B on A, D on C -> D on A, B on C
    tracker = RelationTracker(start, goal)
    # no constructive move: B's goal place C is covered by D, D's goal place A is covered by B
    assert tracker.stuck == {1, 3}
    # moving B (index 1) to the table uncovers A, well placed, whose goal block D is clear: constructive
    assert enables_constructive(tracker, 1) and enables_constructive(tracker, 3)
    assert gn2_block(tracker) == 1  # the first such block
    run = rollout_relational(Gn2Policy(), start, goal)
    names = [a.name("ABCD") for a in run.actions]
    assert run.reached and names[:2] == ["unstack(B,A)", "putdown(B)"] and run.length == optimal_length(start, goal)


def test_gn2_prefers_the_deadlocked_block_whose_departure_enables_a_constructive_move():
    # B on A and D on C are deadlocked with each other; E stands alone, clear and misplaced: its goal is on D.
    start, goal = parse_config("AB,CD,E"), parse_config("AD,CBE")
    tracker = RelationTracker(start, goal)
    assert gn2_block(tracker) == 1
    after = successor(successor(start, Gn2Policy().act(start, goal)), Gn2Policy().act(
        successor(start, Gn2Policy().act(start, goal)), goal))
    assert after == parse_config("A,B,CD,E")


def test_gn2_plans_every_pair_at_three_blocks_optimally():
    plans = list(check_pairs(Gn2Policy(), 3))
    assert len(plans) == 462 and all(p.reached and p.optimal for p in plans)


def test_gn2_reaches_every_goal_at_four_blocks_within_two_moves_of_bfs():
    states = all_states(4)
    dist = distance_matrix(4)
    for g in range(0, len(states), 8):
        for s, start in enumerate(states):
            if s != g:
                run = rollout_relational(Gn2Policy(), start, states[g])
                assert run.reached and dist[g, s] <= run.length <= dist[g, s] + 4


@pytest.mark.parametrize("n", [10, 26])
def test_gn2_plans_are_valid_and_never_shorter_than_the_exact_optimum(n):
    for start, goal in sample_pairs(n, 10, np.random.default_rng(n)):
        run = rollout_relational(Gn2Policy(), start, goal)  # the rollout checks every action's legality
        assert run.reached and run.length >= optimal_length(start, goal)


def test_gn2_is_shorter_than_gn1_in_total_and_more_often_shorter_than_longer():
    rng = np.random.default_rng(48)
    tasks = sample_pairs(20, 60, rng) + [draw_task("tall-towers", 25, rng) for _ in range(30)]
    gn1 = [rollout_relational(Gn1Policy(), s, g).length for s, g in tasks]
    gn2 = [rollout_relational(Gn2Policy(), s, g).length for s, g in tasks]
    shorter = sum(b < a for a, b in zip(gn1, gn2, strict=True))
    longer = sum(b > a for a, b in zip(gn1, gn2, strict=True))
    assert sum(gn2) < sum(gn1) and shorter > 3 * longer


def test_gn2_plans_a_thousand_block_tall_tower_task():
    start, goal = draw_task("tall-towers", 1000, np.random.default_rng(0))
    run = rollout_relational(Gn2Policy(), start, goal)
    assert run.reached and run.length >= lower_bound(start, goal)
