import math

import numpy as np
import pytest

from csql_sim.core.state.state_count import (
    MAX_COUNTED,
    forest_count,
    pair_count,
    rank_state,
    sample_hand_empty,
    sample_pairs,
    sample_state,
    state_count,
    uniform_below,
    unrank_state,
)
from csql_sim.core.state.world import WorldError, all_states


@pytest.mark.parametrize("n", [2, 3, 4, 5, 6])
def test_the_count_formula_is_the_number_of_enumerated_states(n):
    assert state_count(n) == len(all_states(n))


def test_forest_counts_are_the_sets_of_lists():
    assert [forest_count(m) for m in range(8)] == [1, 1, 3, 13, 73, 501, 4051, 37633]


@pytest.mark.parametrize("n", [2, 3, 4, 5])
def test_index_to_state_is_a_bijection_onto_the_enumerated_world(n):
    states = [unrank_state(r, n) for r in range(state_count(n))]
    assert set(states) == {s for s in all_states(n)}
    assert len(set(states)) == len(states)
    assert [rank_state(s) for s in states] == list(range(len(states)))


def test_pairs_pass_two_to_the_63_at_12_blocks_exactly():
    assert pair_count(11) < 2**63 < pair_count(12)
    assert pair_count(26) == state_count(26) * (state_count(26) - 1)


def test_rank_round_trips_at_26_blocks():
    rng = np.random.default_rng(0)
    for _ in range(50):
        state = sample_state(26, rng)
        assert unrank_state(rank_state(state), 26) == state


def test_uniform_below_covers_its_range_evenly_and_is_seeded():
    rng = np.random.default_rng(1)
    draws = [uniform_below(6, rng) for _ in range(6000)]
    counts = np.bincount(draws, minlength=6)
    assert counts.sum() == 6000 and counts.min() > 900 and counts.max() < 1100
    big = 3**200
    again = [uniform_below(big, np.random.default_rng(5)) for _ in range(2)]
    assert again[0] == again[1] and 0 <= again[0] < big


def test_sampled_pairs_are_distinct_seeded_and_in_range():
    first = sample_pairs(12, 20, np.random.default_rng(3))
    assert first == sample_pairs(12, 20, np.random.default_rng(3))
    assert all(a != b and a.n == b.n == 12 for a, b in first)


def test_sampling_at_three_blocks_reaches_every_state_about_equally():
    rng = np.random.default_rng(2)
    seen = [rank_state(sample_state(3, rng)) for _ in range(4400)]
    counts = np.bincount(seen, minlength=22)
    assert counts.min() > 120 and counts.max() < 280  # 200 expected each


def test_counting_and_sampling_reach_hundreds_of_blocks():
    import numpy as np

    from csql_sim.core.state.state_count import rank_state, sample_state, state_count, unrank_state

    assert len(str(state_count(300))) > 600  # exact integers, counted without deep recursion
    state = sample_state(300, np.random.default_rng(3))
    assert state.n == 300 and unrank_state(rank_state(state), 300) == state


def test_the_forest_recurrence_is_the_defining_sum():
    def by_sum(m, memo={0: 1}):  # noqa: B006 - a memo across calls
        if m not in memo:
            memo[m] = sum(math.comb(m - 1, k - 1) * math.factorial(k) * by_sum(m - k) for k in range(1, m + 1))
        return memo[m]

    assert [forest_count(m) for m in range(40)] == [by_sum(m) for m in range(40)]


def test_hand_empty_states_of_a_thousand_blocks_are_drawn_and_ranked_back():
    rng = np.random.default_rng(5)
    state = sample_hand_empty(1000, rng)
    assert state.n == 1000 and state.held is None
    assert unrank_state(rank_state(state), 1000) == state
    assert sample_hand_empty(1000, np.random.default_rng(5)) == state
    with pytest.raises(WorldError):
        sample_hand_empty(MAX_COUNTED + 1, rng)
