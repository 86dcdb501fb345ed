import numpy as np
import pytest

from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model.search import distance, distance_matrix, true_distances
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import all_states


@pytest.mark.parametrize("n", [3, 4])
def test_equal_to_bfs_on_every_pair(n):
    states = [s for s in all_states(n)]
    dist = distance_matrix(n)
    got = np.array([[optimal_length(s, g) for s in states] for g in states])
    assert np.array_equal(got, dist)


@pytest.mark.parametrize(("n", "goals", "starts"), [
    (5, 60, 60), pytest.param(6, 12, 60, marks=pytest.mark.slow)])  # n = 6: the true world's table takes ~20 s
def test_equal_to_bfs_on_a_seeded_sample(n, goals, starts):
    rng = np.random.default_rng(n)
    states = all_states(n)
    for g in rng.choice(len(states), goals, replace=False):
        dist = true_distances(n, int(g))
        for s in rng.choice(len(states), starts, replace=False):
            assert optimal_length(states[s], states[g]) == dist[s]


def test_a_deadlock_costs_one_table_visit():
    start, goal = parse_config("AB,CD"), parse_config("AD,CB")
    assert optimal_length(start, goal) == distance(start, goal) == 6


def test_the_papers_test_task_is_eight_actions():
    assert optimal_length(parse_config("CBA"), parse_config("BAC")) == 8
