import numpy as np
import pytest

from csql_sim.core.model import task_split
from csql_sim.core.model.task_draws import draw_task
from csql_sim.core.state.state_count import sample_pairs


def test_the_held_out_seeds_were_never_used_for_tuning():
    held = {task_split.HELD_OUT_PAIRS_SEED, task_split.HELD_OUT_TALL_SEED}
    assert len(held) == 2 and not held & task_split.TUNING_SEEDS


def test_the_tuning_pairs_are_the_benchmarks_pairs():
    rng = np.random.default_rng(0)
    drawn = {n: sample_pairs(n, 1000, rng) for n in task_split.BENCH_SIZES}
    assert task_split.tuning_pairs((10, 20), 7) == {10: drawn[10][:7], 20: drawn[20][:7]}


def test_the_tuning_towers_are_the_feature_tables_towers():
    rng = np.random.default_rng(0)
    expected = {n: [draw_task("tall-towers", n, rng) for _ in range(3)] for n in (25, 50)}
    assert task_split.tuning_towers((25, 50), 3) == expected


def test_held_out_tasks_are_seeded_and_differ_from_the_tuning_tasks():
    pairs, again = task_split.held_out_pairs((10,), 20), task_split.held_out_pairs((10,), 20)
    assert pairs == again and not set(pairs[10]) & set(task_split.tuning_pairs((10,), 20)[10])
    towers = task_split.held_out_towers((25,), 5)
    assert towers == task_split.held_out_towers((25,), 5) and towers != task_split.tuning_towers((25,), 5)


def test_tuning_pairs_exist_only_at_the_benchmarks_sizes():
    with pytest.raises(ValueError, match="per n of"):
        task_split.tuning_pairs((9,), 10)
