"""The ground Q-classifiers of LQ-CS (:mod:`csql_sim.learners.lifted.learner`): its working memory of one small world.

One ground Q-classifier per (state, target) met, made on demand and kept by index. Its value
in moves is a **start** given by the vocabulary's :class:`Costs` (a lower bound, or 0) plus a
learned excess. A backup looks one move ahead through every legal move (:func:`after`), each
move costing what :meth:`Costs.step` says. :class:`RewardCosts` reads the task's reward alone:
-1 per action and 0 at the goal, in moves (an action of the four-operator domain is half a
move, a pick and its put one).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from csql_sim.core.state.moves import Move, after, last_action, moves
from csql_sim.core.state.world import State

Relations = Callable[[State, State], tuple[tuple[Move, ...], np.ndarray]]
"""A vocabulary's moves and feature vectors of a (state, target) pair."""


class Costs:
    """What a state is worth before any backup, and what a move costs (in moves)."""

    def start(self, state: State, target: State) -> tuple[float, bool]:
        """The state's value before any backup and whether it is final (never backed up: the task is done)."""
        raise NotImplementedError

    def step(self, state: State, start_after: float) -> float:
        """The cost of a move from ``state`` to a state whose start value is ``start_after``."""
        raise NotImplementedError

    def arrival(self, state: State, target: State) -> float:
        """What arriving in ``state`` adds to the cost of the move into it (a tie-break; 0 by default)."""
        return 0.0


class RewardCosts(Costs):
    """The task's reward alone: -1 per action, 0 at the goal; values in moves (``per_move`` actions each).

    A state one action from the goal (the pick of a goal's held block, or the put of the last
    block) is final, worth that action; every other state starts at 0 (optimistic).

    Args:
        per_move: actions per move: 2 with a hand (a pick and a put), 1 in the move domain.
    """

    def __init__(self, per_move: int) -> None:
        self.action = 1.0 / per_move

    def start(self, state: State, target: State) -> tuple[float, bool]:
        if state == target:
            return 0.0, True
        if last_action(state, target) is not None:
            return self.action, True
        return 0.0, False

    def step(self, state: State, start_after: float) -> float:
        return self.action if state.held is not None else 1.0


class PotentialCosts(RewardCosts):
    """:class:`RewardCosts`, and a tie-break: a move into a hand-empty state costs ``early * h`` more.

    ``h`` is a state's fitted estimate of its moves left (:mod:`~csql_sim.learners.lifted.potential`),
    given by ``estimate`` (None until a feature space is fitted: no tie-break then).

    Args:
        per_move: actions per move.
        early: the weight of the tie-break, in moves per unit of h; 0 for none.
    """

    def __init__(self, per_move: int, early: float) -> None:
        super().__init__(per_move)
        self.early = early
        self.estimate: Callable[[State, State], float] | None = None

    def arrival(self, state: State, target: State) -> float:
        if self.estimate is None or not self.early or state.held is not None:
            return 0.0
        return self.early * self.estimate(state, target)


class GroundValues:
    """The ground Q-classifiers, made on demand: one per (state, target) met, by index.

    Each holds the state's start value (:meth:`Costs.start`), its learned excess over it, whether
    it is final, and its successors' indices (through :func:`after`, in move order), remembered;
    and its moves' feature vectors (``relations``), remembered when ``cache``.
    """

    def __init__(self, relations: Relations, costs: Costs, cache: bool = True) -> None:
        self.costs, self._relations, self.cache = costs, relations, cache
        self.index: dict[tuple[State, State], int] = {}
        self.keys: list[tuple[State, State]] = []
        self.low: list[float] = []
        self.final: list[bool] = []
        self.excess: list[float] = []
        self.arrive: list[float] = []
        self.nexts: list[list[int] | None] = []
        self.relations: list[tuple[tuple[Move, ...], np.ndarray] | None] = []

    def of(self, state: State, target: State) -> int:
        """The index of (state, target), made with excess 0 when new."""
        key = (state, target)
        i = self.index.get(key)
        if i is None:
            i = self.index[key] = len(self.keys)
            self.keys.append(key)
            low, final = self.costs.start(state, target)
            self.low.append(low)
            self.final.append(final)
            self.excess.append(0.0)
            self.arrive.append(self.costs.arrival(state, target))
            self.nexts.append(None)
            self.relations.append(None)
        return i

    def successors(self, i: int) -> list[int]:
        """The indices of the hand-empty states after each move of state i (move order)."""
        nexts = self.nexts[i]
        if nexts is None:
            state, target = self.keys[i]
            nexts = self.nexts[i] = [self.of(after(state, m), target) for m in moves(state)]
        return nexts

    def moves_of(self, i: int) -> tuple[tuple[Move, ...], np.ndarray]:
        """State i's legal moves and their feature vectors (moves, width)."""
        found = self.relations[i]
        if found is None:
            found = self._relations(*self.keys[i])
            if self.cache:
                self.relations[i] = found
        return found

    def backup(self, i: int) -> list[float]:
        """Q of every move of state i: its step cost plus the successor's value; the excess becomes the least."""
        state = self.keys[i][0]
        q = [self.costs.step(state, self.low[j]) + self.arrive[j] + self.low[j] + self.excess[j]
             for j in self.successors(i)]
        self.excess[i] = min(q) - self.low[i]
        return q


__all__ = ["Costs", "GroundValues", "PotentialCosts", "RewardCosts"]
