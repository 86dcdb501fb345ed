"""What discovery needs from a world to act in, and the symbolic world that provides it.

:class:`ExplorableWorld` is the protocol: perceive, attempt an action, start over. The
STRIPS world (:class:`SymbolicWorld`) is here; the simulated arm implements the same
protocol (:class:`csql_sim.sim.control.exploration.ArmWorld`), and the job that runs discovery on
the arm (:mod:`csql_sim.jobs.discover`) wires the two.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from csql_sim.core.state.world import BLOCK_NAMES, TABLE, Action, State, all_states, is_legal, successor


@dataclass(frozen=True)
class Attempt:
    """What executing one action did.

    Attributes:
        ok: the primitive's status.
        reason: why it failed, else empty.
        sim_seconds: simulated time it took (0 in the symbolic world).
        events: perturbations that happened during or after it.
        refused: a failure before any motion (the guard saw the action cannot start).
    """

    ok: bool
    reason: str = ""
    sim_seconds: float = 0.0
    events: tuple[str, ...] = ()
    refused: bool = False


class ExplorableWorld(Protocol):
    """A world the agent can explore: perceive, attempt an action, start over."""

    n: int

    def perceive(self) -> State | None:
        """The perceived state, or None when perception cannot name one."""

    def attempt(self, action: Action) -> Attempt:
        """Execute ``action`` (legal or not) and report the primitive's status."""

    def restart(self) -> None:
        """Begin a new episode from a random state (after perception failed)."""


@dataclass
class SymbolicWorld:
    """The STRIPS blocks world as an explorable world.

    Args:
        n: number of blocks.
        rng: the one generator (start states, perturbations).
        perturb: knock a tower's top block onto the table with ``knock_probability``
            after an action (noise the induction must cope with).
        knock_probability: chance of one knock per transition under ``perturb``.
    """

    n: int
    rng: np.random.Generator
    perturb: bool = False
    knock_probability: float = 0.05
    state: State = field(init=False)

    def __post_init__(self) -> None:
        self.restart()

    def perceive(self) -> State | None:  # noqa: D102
        return self.state

    def attempt(self, action: Action) -> Attempt:  # noqa: D102
        ok = is_legal(self.state, action)
        if ok:
            self.state = successor(self.state, action)
        events: tuple[str, ...] = ()
        if self.perturb and self.rng.random() < self.knock_probability:
            events = (knock_tower(self, self.rng),)
        return Attempt(ok, "" if ok else "preconditions do not hold", events=events, refused=not ok)

    def restart(self) -> None:  # noqa: D102
        resting = [s for s in all_states(self.n) if s.held is None]
        self.state = resting[int(self.rng.integers(len(resting)))]


def knock_tower(world: SymbolicWorld, rng: np.random.Generator) -> str:
    """Move the top block of a random tower of height >= 2 onto the table (a symbolic nudge)."""
    tops = [i for i in range(world.n) if world.state.is_clear(i) and world.state.support[i] >= 0]
    if not tops:
        return "knock skipped: no tower"
    block = tops[int(rng.integers(len(tops)))]
    support = list(world.state.support)
    support[block] = TABLE
    world.state = State(tuple(support))
    return f"knocked {BLOCK_NAMES[block]} onto the table"


