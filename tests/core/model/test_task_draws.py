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
