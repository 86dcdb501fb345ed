"""A task: a start and a goal configuration, and when it counts as achieved.

As in panda-gym, the task decides success from what is observed: the executor on the
arm and the Gymnasium environments both ask :meth:`Task.is_success` with the perceived
state, never the plan.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

from csql_sim.core.model.search import true_distances
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import TEST_GOAL, TEST_START, BlocksWorld, State, WorldError


@dataclass(frozen=True)
class Task:
    """Reach ``goal`` from ``start``.

    Attributes:
        start: the start configuration.
        goal: the goal configuration (same number of blocks).

    """

    start: State
    goal: State

    def __post_init__(self) -> None:
        if self.start.n != self.goal.n:
            raise WorldError(f"start has {self.start.n} blocks but goal has {self.goal.n}")

    @property
    def n(self) -> int:
        """Number of blocks."""
        return self.start.n

    @staticmethod
    def is_success(perceived: State | None, goal: State) -> bool:
        """Whether the perceived state is the goal (``None``: nothing perceived)."""
        return perceived is not None and perceived == goal


MAXIMAL_PAIRS = {2: ("AB", "BA"), 4: ("CBDA", "BCDA"), 5: ("BCDEA", "BDCEA")}
"""The first pair of maximal optimal length per n (4 (n - 1) actions), tabulated; a test recomputes them."""


def test_task(n: int) -> Task:
    """The task learning curves are measured on (Figure 7).

    For n = 3 the paper's: A on B on C to C on A on B (8 actions). For other n, a pair of
    maximal optimal length: scanning goals in state order, the first goal whose farthest
    start is as far as any, and its first farthest start (n = 2: AB to BA, 4 actions;
    n = 4: CBDA to BCDA, 12; n = 5: BCDEA to BDCEA, 16; n = 6 is computed once).
    """
    if n == 3:
        return Task(parse_config(TEST_START, 3), parse_config(TEST_GOAL, 3))
    if n in MAXIMAL_PAIRS:
        start, goal = MAXIMAL_PAIRS[n]
        return Task(parse_config(start, n), parse_config(goal, n))
    states = BlocksWorld.of(n).states
    start, goal = first_maximal_pair(n)
    return Task(states[start], states[goal])


@functools.cache
def first_maximal_pair(n: int) -> tuple[int, int]:
    """(start, goal) state indices of the first pair of maximal optimal length (a BFS per goal)."""
    best, pair = -1, (0, 0)
    for goal in range(len(BlocksWorld.of(n).states)):
        dist = true_distances(n, goal)
        far = int(dist.max())
        if far > best:
            best, pair = far, (int(dist.argmax()), goal)
    return pair


test_task.__test__ = False  # type: ignore[attr-defined]  # not a pytest test despite the name
