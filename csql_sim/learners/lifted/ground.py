"""The ground Q-classifiers of LQ-CS (:mod:`csql_sim.learners.lifted.ql`): its working memory of one small world.

One ground Q-classifier per (state, target) met, made on demand and kept by index: the
value of the state in moves is its misplaced blocks (a lower bound) plus a learned excess.
A backup looks one move ahead through every legal move (:func:`after`), each move costing
1 plus ``early`` per block still misplaced after it.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from csql_sim.core.state.goal_relations import well_placed
from csql_sim.core.state.moves import Move, after, moves
from csql_sim.core.state.world import State

Relations = Callable[[State, State], tuple[tuple[Move, ...], np.ndarray]]
"""A vocabulary's moves and feature vectors of a (state, target) pair."""


class GroundValues:
    """The ground Q-classifiers, made on demand: one per (state, target) met, by index.

    Each holds the state's misplaced blocks (the lower bound of its value in moves), its learned
    excess over that bound and its successors' indices (through :func:`after`, in move order),
    remembered; and its moves' feature vectors (``relations``), remembered when ``cache``.
    """

    def __init__(self, relations: Relations, early: float = 0.0, cache: bool = True) -> None:
        self.early, self._relations, self.cache = early, relations, cache
        self.index: dict[tuple[State, State], int] = {}
        self.keys: list[tuple[State, State]] = []
        self.low: list[int] = []
        self.excess: list[float] = []
        self.nexts: list[list[int] | None] = []
        self.relations: list[tuple[tuple[Move, ...], np.ndarray] | None] = []

    def of(self, state: State, target: State) -> int:
        """The index of (state, target), made with excess 0 when new."""
        key = (state, target)
        i = self.index.get(key)
        if i is None:
            i = self.index[key] = len(self.keys)
            self.keys.append(key)
            self.low.append(well_placed(state, target).count(False))
            self.excess.append(0.0)
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
        """Q of every move of state i: 1 + early x misplaced(s') + Q(s'); the excess becomes the least."""
        q = [1.0 + (1.0 + self.early) * self.low[j] + self.excess[j] for j in self.successors(i)]
        self.excess[i] = min(q) - self.low[i]
        return q


__all__ = ["GroundValues"]
