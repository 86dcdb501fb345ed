"""Random blocks-world tasks of up to 1,000 blocks, seeded: the distributions problems are drawn from.

* ``tall-towers``: the planning competitions' recent blocks-world tasks. The blocks in a
  random order, cut into towers (bottom-up) with a cut after each block with probability
  1/10, so towers are about ten high; drawn once for the start and once for the goal.
* ``uniform``: every hand-empty configuration equally likely, by counting and unranking
  (:func:`csql_sim.core.state.state_count.sample_hand_empty`, exact integers); towers are
  about sqrt(n) high.

Both draw from one :class:`numpy.random.Generator`, the start before the goal, so a seed
gives the same tasks on every machine.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from csql_sim.core.state.state import State
from csql_sim.core.state.state_count import MAX_COUNTED, sample_hand_empty
from csql_sim.core.state.world import MIN_BLOCKS, TABLE, WorldError

CUT = 0.1
"""The probability of a cut after each block in ``tall-towers``."""
MAX_DRAWN = 1000
"""The most blocks a drawn task has."""


def tall_towers(n: int, rng: np.random.Generator) -> State:
    """A random permutation of the n blocks cut into towers after each block with probability :data:`CUT`."""
    order = rng.permutation(n).tolist()
    cuts = (rng.random(n - 1) < CUT).tolist()
    support = [TABLE] * n
    for i in range(1, n):
        if not cuts[i - 1]:
            support[order[i]] = order[i - 1]
    return State(tuple(support))


DISTRIBUTIONS: dict[str, Callable[[int, np.random.Generator], State]] = {
    "tall-towers": tall_towers,
    "uniform": sample_hand_empty,
}
"""The distributions of hand-empty configurations, by name."""


def draw_task(distribution: str, n: int, rng: np.random.Generator) -> tuple[State, State]:
    """A start and a goal of n blocks from ``distribution``, the start drawn first."""
    if distribution not in DISTRIBUTIONS:
        raise WorldError(f"unknown distribution {distribution!r}; expected one of {', '.join(DISTRIBUTIONS)}")
    if not isinstance(n, int) or not MIN_BLOCKS <= n <= min(MAX_DRAWN, MAX_COUNTED):
        raise WorldError(f"drawn tasks have {MIN_BLOCKS}..{MAX_DRAWN} blocks, got {n!r}")
    draw = DISTRIBUTIONS[distribution]
    start = draw(n, rng)
    return start, draw(n, rng)
