"""Measuring: the lower bound, the optimum within a budget (proven or bounded), CP-SAT when installed."""

import numpy as np
import pytest

from csql_sim.core.measure.bounds import (
    Bound,
    bounded_optimum,
    cpsat_available,
    cpsat_optimum,
    hitting_set_optimum,
    lower_bound,
)
from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model.task_draws import draw_task, tall_towers
from csql_sim.core.state.notation import parse_config as parse_large
from csql_sim.core.state.state_count import sample_hand_empty
from csql_sim.core.state.world import WorldError


def test_the_lower_bound_is_twice_the_misplaced_blocks():
    assert lower_bound(parse_large("CBA"), parse_large("BAC")) == 6  # all three misplaced; the optimum is 8
    assert lower_bound(parse_large("AB,C"), parse_large("ABC")) == 2
    with pytest.raises(WorldError):
        lower_bound(parse_large("AB+C"), parse_large("ABC"))


def test_with_time_enough_the_optimum_is_proven_and_exact():
    rng = np.random.default_rng(3)
    for n in (5, 8, 12):
        for _ in range(15):
            start, goal = sample_hand_empty(n, rng), sample_hand_empty(n, rng)
            bound = bounded_optimum(start, goal, budget_s=60)
            assert bound.proven and bound.lower == optimal_length(start, goal) >= lower_bound(start, goal)


def test_out_of_time_the_optimum_is_bounded_and_a_plan_narrows_it():
    start, goal = draw_task("tall-towers", 200, np.random.default_rng(0))
    bound = bounded_optimum(start, goal, budget_s=0.0)
    assert not bound.proven and lower_bound(start, goal) <= bound.lower < bound.upper
    assert "bounded" in bound.text()
    narrowed = bound.narrowed(bound.lower + 2)
    assert narrowed.upper == bound.lower + 2 and bound.narrowed(bound.upper + 10) == bound
    with pytest.raises(WorldError):
        bound.narrowed(bound.lower - 2)
    assert Bound(8, 8).text() == "8 (proven)"


@pytest.mark.skipif(not cpsat_available(), reason="OR-Tools is a bench extra: pip install '.[bench]'")
def test_cpsat_gives_the_same_optimum_as_the_search():
    rng = np.random.default_rng(4)
    for _ in range(10):
        start, goal = tall_towers(16, rng), tall_towers(16, rng)
        assert cpsat_optimum(start, goal, 30).lower == bounded_optimum(start, goal, 60).lower


@pytest.mark.skipif(not cpsat_available(), reason="OR-Tools is a bench extra: pip install '.[bench]'")
def test_hitting_sets_give_the_same_optimum_as_the_search():
    rng = np.random.default_rng(5)
    pairs = [(tall_towers(n, rng), tall_towers(n, rng)) for n in (8, 10, 12, 16) for _ in range(6)]
    pairs += [(sample_hand_empty(n, rng), sample_hand_empty(n, rng)) for n in (8, 12) for _ in range(6)]
    deadlocked = 0
    for start, goal in pairs:
        bound, exact = hitting_set_optimum(start, goal, 30), bounded_optimum(start, goal, 60)
        assert exact.proven and bound.proven and bound.lower == exact.lower and bound.method == "hitting set"
        deadlocked += exact.lower > lower_bound(start, goal)
    assert deadlocked >= len(pairs) // 2  # the table visits are what is being checked
    hurried = hitting_set_optimum(*pairs[0], budget_s=0.0)
    assert hurried.lower <= bounded_optimum(*pairs[0], 60).lower <= hurried.upper
