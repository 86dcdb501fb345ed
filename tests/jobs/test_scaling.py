"""The scaling study: the same cells whichever engine runs LT-QL, and each cell's peak memory."""

import csv
import io

import numpy as np
import pytest

from csql_sim.core.model.search import count_optimal_greedy
from csql_sim.jobs.scaling import COLUMNS, csv_text, peak_rss_bytes, reset_peak_rss, run_cell, run_scaling
from csql_sim.learners.training.tabular import make_learner


def test_lt_ql_cells_are_the_same_on_both_engines():
    fast = run_cell("lt-ql", 3, seed=1, max_trials=300)
    ref = run_cell("lt-ql", 3, seed=1, max_trials=300, engine="reference")
    assert (fast.trials, fast.steps, fast.optimal_pairs) == (ref.trials, ref.steps, ref.optimal_pairs)
    assert fast.pairs == 462 and fast.peak_rss_mb > 0 and ref.peak_rss_mb > 0


def test_a_reached_cell_is_all_optimal_on_the_reference_engine_too():
    (row,) = run_scaling([2], ["lt-ql"], seed=0, max_trials=400)
    assert row.trials is not None and row.optimal_pairs == row.pairs == 20
    assert row.trials % 50  # no test task after the last trial: training that long is the same trajectory
    params = {"t_decay": (0.0005 / 0.5) ** (1.0 / (0.6 * 400))}
    counts = []
    for trials in (row.trials - 4, row.trials):  # checked every 1% of 400 trials
        learner = make_learner("lt-ql", 2, params, seed=0, engine="reference")
        learner.train(trials)
        counts.append(count_optimal_greedy(learner.greedy_table().best, 2))
    assert counts[0] < counts[1] == 20


def test_csv_has_each_cells_peak_memory():
    rows = run_scaling([2], ["lt-ql", "cs-ql"], seed=0, max_trials=100)
    table = list(csv.DictReader(io.StringIO(csv_text(rows))))
    assert tuple(table[0]) == COLUMNS and [r["method"] for r in table] == ["lt-ql", "cs-ql"]
    for r, row in zip(table, rows, strict=True):
        assert row.peak_rss_mb > 10 and float(r["peak_rss_mb"]) == pytest.approx(row.peak_rss_mb, abs=0.05)


def test_peak_rss_sees_an_allocation_after_a_reset():
    if not reset_peak_rss():
        pytest.skip("this system cannot reset the peak resident set size")
    before = peak_rss_bytes()
    block = np.ones(80_000_000 // 8)  # 80 MB, touched
    del block
    assert peak_rss_bytes() >= before + 70_000_000


def test_modes_side_by_side_and_the_sweep_needs_few_trials():
    rows = run_scaling([3], ["cs-ql"], seed=0, max_trials=200, modes=("trials", "replay", "sweep"))
    assert [r.mode for r in rows] == ["trials", "replay", "sweep"]
    by = {r.mode: r for r in rows}
    assert by["replay"].replay_backups > 0 and by["replay"].experienced_pairs <= by["replay"].legal_pairs == 42
    assert by["trials"].replay_backups == 0 and by["trials"].sweep_backups == 0
    for r in rows:  # the reached cells are all optimal; a capped cell's count is exact
        assert (r.trials is not None) == (r.optimal_pairs == r.pairs == 462)
        assert r.optimal_steps >= r.optimal_pairs
    table = list(csv.DictReader(io.StringIO(csv_text(rows))))
    assert [t["mode"] for t in table] == ["trials", "replay", "sweep"]
