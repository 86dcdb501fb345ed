import numpy as np
import pytest

from csql_sim.core.measure.bounds import lower_bound
from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model.search import distance, distance_matrix
from csql_sim.core.model.task_draws import draw_task
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.gn2 import (
    READINGS,
    Gn2Policy,
    constructive,
    constructive_run,
    enables_constructive,
    gn2_block,
)
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.policies.rollout import check_pairs
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.relation_tracker import RelationTracker
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.core.state.world import all_states


def test_gn2_on_a_hand_worked_example_breaks_the_deadlock_where_gn1_does_not():
    """CBA,ED -> B,EADC (towers bottom-up; goal: B alone, A on E, D on A, C on D), worked by hand.

    E is in position; A, B, C, D are misplaced, so every plan moves at least 4 blocks. The
    clear blocks are A and D, and no move is constructive: A's goal place E is covered by D,
    and D's goal place A is not in position. A and D are deadlocked: D waits for A's final
    move, A waits for D to leave E. Both departures enable a constructive move at once
    (A leaving uncovers B, whose goal is the table; D leaving uncovers E, A's goal place), so
    the one-move lookahead cannot choose. The hitting set can: A's visit to the table ends no
    wait (D still waits for A's *final* move), D's does. GN2 tables D:
    D-T, A-E, B-T, D-A, C-D: 5 moves, 10 actions, one block visiting the table: the optimum
    (2 x (4 misplaced + 1 visitor), and BFS's distance). GN1 tables A first (the first
    deadlocked block), then must table D too: 6 moves, 12 actions.
    """
    start, goal = parse_config("CBA,ED"), parse_config("B,EADC")
    a, d = 0, 3
    tracker = RelationTracker(start, goal)
    assert tracker.stuck == {a, d} and not any(constructive(tracker, b) for b in range(5))
    assert enables_constructive(tracker, a) and enables_constructive(tracker, d)
    assert d in tracker.cover and a not in tracker.cover
    assert gn2_block(tracker) == d and gn2_block(tracker, "enables") == a
    run = rollout_relational(Gn2Policy(), start, goal)
    names = [x.name("ABCDE") for x in run.actions]
    assert names == ["unstack(D,E)", "putdown(D)", "unstack(A,B)", "stack(A,E)", "unstack(B,C)", "putdown(B)",
                     "pickup(D)", "stack(D,A)", "pickup(C)", "stack(C,D)"]
    assert run.length == 10 == optimal_length(start, goal) == distance(start, goal)
    assert rollout_relational(Gn1Policy(), start, goal).length == 12


def test_every_reading_plans_validly_and_an_unknown_one_is_refused():
    start, goal = draw_task("tall-towers", 30, np.random.default_rng(3))
    for reading in READINGS:
        run = rollout_relational(Gn2Policy(reading), start, goal)
        assert run.reached and run.length >= optimal_length(start, goal)
    with pytest.raises(ValueError, match="unknown GN2 reading"):
        Gn2Policy("cleverest")


def test_constructive_run_counts_the_moves_that_follow_a_table_move():
    start, goal = parse_config("CA,B"), parse_config("CBA")
    tracker = RelationTracker(start, goal)
    # A to the table uncovers C (in position); then B onto C, then A onto B: two constructive moves
    assert constructive_run(tracker, 0) == 2


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


def test_gn2_is_never_longer_than_gn1_on_tall_towers_and_rarely_on_random_pairs():
    """GN2 is never longer than GN1 on this seeded sample of tall towers; on random pairs it sometimes is.

    Measured on larger samples (seed 4801): longer than GN1 on 0 of 100 tall towers at n = 25,
    1 of 100 at n = 50 (by 2 actions); on 4 of 500 pairs at n = 10 and 18 of 500 at n = 20
    (by at most 6 actions), shorter on 81 and 284 of them.
    """
    rng = np.random.default_rng(48)
    towers = [draw_task("tall-towers", 25, rng) for _ in range(30)]
    pairs = sample_pairs(20, 60, rng)
    for tasks, most_longer in ((towers, 0), (pairs, len(pairs) // 10)):
        gn1 = [rollout_relational(Gn1Policy(), s, g).length for s, g in tasks]
        gn2 = [rollout_relational(Gn2Policy(), s, g).length for s, g in tasks]
        shorter = sum(b < a for a, b in zip(gn1, gn2, strict=True))
        longer = sum(b > a for a, b in zip(gn1, gn2, strict=True))
        assert longer <= most_longer and shorter > 3 * max(longer, 1) and sum(gn2) < sum(gn1)


def test_gn2_plans_a_thousand_block_tall_tower_task():
    start, goal = draw_task("tall-towers", 1000, np.random.default_rng(0))
    run = rollout_relational(Gn2Policy(), start, goal)
    assert run.reached and run.length >= lower_bound(start, goal)
