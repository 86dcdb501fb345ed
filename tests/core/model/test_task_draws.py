"""Random tasks: tall towers about ten high, uniform configurations, the same per seed."""

import numpy as np
import pytest

from csql_sim.core.model.task_draws import DISTRIBUTIONS, draw_task, tall_towers
from csql_sim.core.state.world import WorldError


def test_tall_towers_are_about_ten_high_and_use_every_block_once():
    rng = np.random.default_rng(0)
    heights = []
    for _ in range(20):
        state = tall_towers(500, rng)
        towers = state.towers()
        assert sorted(b for t in towers for b in t) == list(range(500)) and state.held is None
        heights += [len(t) for t in towers]
    assert 8.5 < np.mean(heights) < 11.5


@pytest.mark.parametrize("distribution", sorted(DISTRIBUTIONS))
def test_a_seed_gives_the_same_tasks_and_another_seed_others(distribution):
    a = draw_task(distribution, 300, np.random.default_rng(1))
    assert a == draw_task(distribution, 300, np.random.default_rng(1))
    assert a != draw_task(distribution, 300, np.random.default_rng(2))
    assert a[0] != a[1]


@pytest.mark.parametrize("n", [1, 1001])
def test_sizes_and_names_out_of_range_are_refused(n):
    with pytest.raises(WorldError):
        draw_task("tall-towers", n, np.random.default_rng(0))
    with pytest.raises(WorldError):
        draw_task("towers", 10, np.random.default_rng(0))


def test_max_height_draws_only_tasks_whose_towers_fit_and_the_same_per_seed():
    from csql_sim.core.model.task_draws import tallest

    tasks = [draw_task("tall-towers", 30, np.random.default_rng(7), max_height=12) for _ in range(2)]
    assert tasks[0] == tasks[1]
    rng = np.random.default_rng(3)
    drawn = [draw_task("tall-towers", 30, rng, max_height=12) for _ in range(20)]
    assert all(tallest(s) <= 12 and tallest(g) <= 12 for s, g in drawn)
    assert max(max(tallest(s), tallest(g)) for s, g in drawn) == 12  # the limit, not a tighter one
    assert draw_task("tall-towers", 30, np.random.default_rng(3), max_height=12) == drawn[0]


def test_fit_probability_is_the_share_of_draws_that_fit():
    from csql_sim.core.model.task_draws import fit_probability, tallest

    assert fit_probability(12, 15) == 1.0 and fit_probability(5, 1) == pytest.approx(0.1 ** 4)
    rng = np.random.default_rng(0)
    share = np.mean([tallest(tall_towers(30, rng)) <= 10 for _ in range(4000)])
    assert share == pytest.approx(fit_probability(30, 10), abs=0.03)


@pytest.mark.parametrize("distribution, height, needle", [
    ("tall-towers", 3, "probability"), ("uniform", 10, "tall-towers distribution"), ("tall-towers", 0, "positive")])
def test_a_max_height_the_draw_cannot_meet_is_refused(distribution, height, needle):
    with pytest.raises(WorldError, match=needle):
        draw_task(distribution, 30, np.random.default_rng(0), max_height=height)
