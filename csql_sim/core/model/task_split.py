"""Tuning tasks and held-out tasks: which drawn tasks a design choice may look at, and which report.

**Tuning tasks** are every task drawn so far by the project's measurements, all from the
seeds of :data:`TUNING_SEEDS`:

* the benchmark's pairs: one generator seeded 0 draws 1,000 uniform pairs at each n of
  :data:`BENCH_SIZES` in turn (``benchmarks/lifted_benchmark.py``, ``benchmarks/lifted_learning_seeds.py``,
  ``benchmarks/features_table.py``, ``benchmarks/lifted_learning_curves.py``, the check pairs of 100 pairs
  at n = 20 on which ``early`` = 0.02 was chosen);
* the tall towers of ``csql-sim problems --seed 0`` (``benchmarks/large_problems.py``: 30 per
  size at 25-500 blocks, on whose 100- and 200-block spreads ``least-stuck`` was left out;
  ``benchmarks/features_table.py``'s tall towers, seed 0);
* ``benchmarks/features_table_move_excess.py`` (seed 1: 5-block pairs and the 12-block tall towers
  against whose optimum ``least-stuck`` was measured), ``benchmarks/execute_pddl.py``
  (seed 2026) and the byte-identity runs (seeds 1, 2, 5).
* GN2's reading (:mod:`csql_sim.core.policies.gn2`) was chosen on the first 10 tall towers per
  n of :func:`tuning_towers` at 25, 50 and 100, 30 per n for GN2 / GN1, and the first 100
  benchmark pairs at n = 20 (``benchmarks/gn2_readings.py``); how often it is longer than GN1
  was counted on pairs and tall towers of seed 4801.

The generated-feature learner's K, sweep length, split rule and pick rule were chosen on the
benchmark's pairs too. Those tasks stay the tuning tasks: a figure measured on them says
how well the choices fit the tasks they were made on.

**Held-out tasks** are drawn from seeds no measurement used before and no design choice
looked at: :data:`HELD_OUT_PAIRS_SEED` for uniform pairs, :data:`HELD_OUT_TALL_SEED` for
tall towers. They are for reporting only: a change tuned on them would make them tuning
tasks, and the next report would need new seeds (and this docstring would say so).
"""

from __future__ import annotations

import numpy as np

from csql_sim.core.model.task_draws import draw_task
from csql_sim.core.state.state import State
from csql_sim.core.state.state_count import sample_pairs

Task = tuple[State, State]

BENCH_SIZES = (6, 7, 8, 10, 15, 20, 26)
"""The sizes the benchmark's pair generator draws 1,000 pairs for, in this order (seed 0)."""
BENCH_PAIRS = 1000
"""Pairs per size the benchmark's generator draws."""
TUNING_SEEDS = frozenset({0, 1, 2, 5, 2026, 4801})
"""Every task-drawing seed a measurement or design choice of the project used (module docstring)."""
HELD_OUT_PAIRS_SEED = 4848
"""The generator of the held-out uniform pairs: never used before issue 48's report."""
HELD_OUT_TALL_SEED = 4849
"""The generator of the held-out tall towers: never used before issue 48's report."""


def tuning_pairs(sizes: tuple[int, ...], count: int) -> dict[int, list[Task]]:
    """The first ``count`` of the benchmark's pairs at each n of ``sizes`` (each one of :data:`BENCH_SIZES`)."""
    if not set(sizes) <= set(BENCH_SIZES) or count > BENCH_PAIRS:
        raise ValueError(f"the benchmark's pairs are {BENCH_PAIRS} per n of {BENCH_SIZES}")
    rng = np.random.default_rng(0)
    drawn = {n: sample_pairs(n, BENCH_PAIRS, rng) for n in BENCH_SIZES}
    return {n: drawn[n][:count] for n in sizes}


def tuning_towers(sizes: tuple[int, ...], count: int) -> dict[int, list[Task]]:
    """``count`` tall-tower tasks per n, drawn size after size by one generator seeded 0 (the feature table's)."""
    return _towers(sizes, count, 0)


def held_out_pairs(sizes: tuple[int, ...], count: int) -> dict[int, list[Task]]:
    """``count`` uniform pairs per n, drawn size after size by one generator seeded :data:`HELD_OUT_PAIRS_SEED`."""
    rng = np.random.default_rng(HELD_OUT_PAIRS_SEED)
    return {n: sample_pairs(n, count, rng) for n in sizes}


def held_out_towers(sizes: tuple[int, ...], count: int) -> dict[int, list[Task]]:
    """``count`` tall-tower tasks per n, drawn size after size by one generator seeded :data:`HELD_OUT_TALL_SEED`."""
    return _towers(sizes, count, HELD_OUT_TALL_SEED)


def _towers(sizes: tuple[int, ...], count: int, seed: int) -> dict[int, list[Task]]:
    rng = np.random.default_rng(seed)
    return {n: [draw_task("tall-towers", n, rng) for _ in range(count)] for n in sizes}
