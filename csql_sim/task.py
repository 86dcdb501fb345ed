"""A task: a start and a goal configuration, and when it counts as achieved.

As in panda-gym, the task decides success from what is observed: the executor on the
arm and the Gymnasium environments both ask :meth:`Task.is_success` with the perceived
state, never the plan.
"""

from __future__ import annotations

from dataclasses import dataclass

from csql_sim.notation import parse_config
from csql_sim.world import TEST_GOAL, TEST_START, BlocksWorld, State, WorldError


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


def test_task(n: int) -> Task:
    """The task learning curves are measured on (Figure 7).

    For n = 3 the paper's: A on B on C to C on A on B (8 actions). For other n, the last
    state of the stable order to the first (all blocks on the table).
    """
    if n == 3:
        return Task(parse_config(TEST_START, 3), parse_config(TEST_GOAL, 3))
    states = BlocksWorld.of(n).states
    return Task(states[-1], states[0])


test_task.__test__ = False  # type: ignore[attr-defined]  # not a pytest test despite the name
