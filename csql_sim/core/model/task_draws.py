"""Random blocks-world tasks of up to 1,000 blocks, seeded: the distributions problems are drawn from.

* ``tall-towers``: the planning competitions' recent blocks-world tasks. The blocks in a
  random order, cut into towers (bottom-up) with a cut after each block with probability
  1/10, so towers are about ten high; drawn once for the start and once for the goal.
* ``uniform``: every hand-empty configuration equally likely, by counting and unranking
  (:func:`csql_sim.core.state.state_count.sample_hand_empty`, exact integers); towers are
  about sqrt(n) high.

Both draw from one :class:`numpy.random.Generator`, the start before the goal, so a seed
gives the same tasks on every machine.

``max_height`` H keeps only tasks whose start and goal towers are at most H high
(``tall-towers`` only): pairs are drawn from the same generator until one fits (rejection
sampling, so still one stream per seed). An H that a pair fits with probability below
:data:`MIN_FIT` (:func:`fit_probability`, exact) is refused before anything is drawn.
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


MIN_FIT = 1e-4
"""The least probability that a drawn pair fits ``max_height`` (at most 10,000 draws expected)."""
MAX_TRIES = 200_000
"""The most pairs drawn for one task under ``max_height`` (a miss has probability below e^-20)."""


def fit_probability(n: int, height: int, cut: float = CUT) -> float:
    """The probability that one ``tall-towers`` configuration of n blocks has no tower above ``height``.

    Exact: the towers are the runs between independent cuts, so f(i), the probability that
    the first i blocks end a tower and no tower so far is too tall, sums over the last tower's length.
    """
    f = [1.0] + [0.0] * n
    for i in range(1, n + 1):
        f[i] = sum(f[i - k] * (1 - cut) ** (k - 1) * (cut if i > k else 1.0) for k in range(1, min(height, i) + 1))
    return f[n]


def tallest(state: State) -> int:
    """The height of the state's tallest tower."""
    return max(len(t) for t in state.towers())


def check_max_height(distribution: str, n: int, max_height: int | None) -> None:
    """Refuse, with one line, a ``max_height`` the draw cannot meet in a bounded number of tries."""
    if max_height is None:
        return
    if distribution != "tall-towers":
        raise WorldError(f"a maximum height is for the tall-towers distribution, not {distribution!r}")
    if not isinstance(max_height, int) or max_height < 1:
        raise WorldError(f"the maximum height must be a positive integer, got {max_height!r}")
    fit = fit_probability(n, max_height) ** 2
    if fit < MIN_FIT:
        raise WorldError(f"a tall-towers task of {n} blocks has every tower at most {max_height} high with "
                         f"probability {fit:.1e}; give a larger maximum height (drawing would take too long)")


def draw_task(distribution: str, n: int, rng: np.random.Generator,
              max_height: int | None = None) -> tuple[State, State]:
    """A start and a goal of n blocks from ``distribution``, the start drawn first (towers <= ``max_height``)."""
    if distribution not in DISTRIBUTIONS:
        raise WorldError(f"unknown distribution {distribution!r}; expected one of {', '.join(DISTRIBUTIONS)}")
    if not isinstance(n, int) or not MIN_BLOCKS <= n <= min(MAX_DRAWN, MAX_COUNTED):
        raise WorldError(f"drawn tasks have {MIN_BLOCKS}..{MAX_DRAWN} blocks, got {n!r}")
    check_max_height(distribution, n, max_height)
    draw = DISTRIBUTIONS[distribution]
    for _ in range(MAX_TRIES if max_height is not None else 1):
        start = draw(n, rng)
        goal = draw(n, rng)
        if max_height is None or max(tallest(start), tallest(goal)) <= max_height:
            return start, goal
    raise WorldError(f"no tall-towers task of {n} blocks with towers at most {max_height} high in {MAX_TRIES:,} "
                     f"draws")
