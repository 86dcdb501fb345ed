import numpy as np
import pytest

from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model.search import distance_matrix
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.policies.rollout import check_pairs
from csql_sim.core.state.move_relations import target_goal
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.core.state.world import all_states


def test_gn1_plans_every_pair_at_three_blocks_optimally_through_the_policy_interface():
    plans = list(check_pairs(Gn1Policy(), 3))
    assert len(plans) == 462 and all(p.reached and p.optimal for p in plans)


def test_gn1_solves_every_pair_at_four_blocks_and_is_never_far_from_optimal():
    states = [s for s in all_states(4)]
    dist = distance_matrix(4)
    lengths, optima = [], []
    for g in range(0, len(states), 4):  # every fourth goal, every start: 3,968 pairs
        for s, start in enumerate(states):
            if s != g:
                run = rollout_relational(Gn1Policy(), start, states[g])
                assert run.reached, (start, states[g], run.reason)
                lengths.append(run.length)
                optima.append(dist[g, s])
    lengths, optima = np.array(lengths), np.array(optima)
    assert (lengths >= optima).all() and (lengths <= optima + 4).all()
    assert 0.99 < np.mean(lengths == optima) < 1  # GN1 is not optimal everywhere


@pytest.mark.parametrize("n", [10, 26])
def test_gn1_solves_seeded_random_pairs_at_large_n(n):
    for start, goal in sample_pairs(n, 10, np.random.default_rng(n)):
        run = rollout_relational(Gn1Policy(), start, goal)
        assert run.reached and run.length >= optimal_length(start, goal)


def test_a_goal_that_holds_a_block_is_built_hand_empty_then_picked():
    start, goal = parse_config("ABC"), parse_config("AB+C")
    assert target_goal(start, goal) == start
    run = rollout_relational(Gn1Policy(), start, goal)
    assert [a.name() for a in run.actions] == ["unstack(C,B)"]
