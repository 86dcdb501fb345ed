"""The given atoms as LQ-CS's vocabulary: nine relations of a move written by hand.

:class:`GivenAtoms` reads :class:`~csql_sim.core.state.move_relations.MoveRelations` (names
in :data:`~csql_sim.core.state.atom_names.ATOMS`) towards the goal without its held block
(:func:`~csql_sim.core.state.move_relations.target_goal`); its ground values start at the
misplaced blocks, a lower bound (:class:`MisplacedCosts`). These are hand-written concepts:
the generated features' learner never imports this module.
"""

from __future__ import annotations

import numpy as np

from csql_sim.core.state.atom_names import ATOMS
from csql_sim.core.state.goal_relations import well_placed
from csql_sim.core.state.move_relations import MoveRelations, target_goal
from csql_sim.core.state.moves import Move
from csql_sim.core.state.world import State
from csql_sim.learners.lifted.ground import Costs
from csql_sim.learners.lifted.rules import Literals
from csql_sim.learners.lifted.vocab import Vocabulary


class MisplacedCosts(Costs):
    """Values start at the misplaced blocks (a lower bound; final at 0); a move costs 1 + ``early`` per block left."""

    def __init__(self, early: float) -> None:
        self.early = early

    def start(self, state: State, target: State) -> tuple[float, bool]:
        low = well_placed(state, target).count(False)
        return float(low), low == 0

    def step(self, state: State, start_after: float) -> float:
        return 1.0 + self.early * start_after


class GivenAtoms(Vocabulary):
    """The nine relations of a move written by hand (:data:`ATOMS`), of which the classifiers read ``read``.

    An atom not read is 0 in every feature vector and left out of every cover, so it is ``#`` in
    every condition and no split can choose it.
    """

    name = "given"
    width = len(ATOMS)

    def __init__(self, read: tuple[str, ...] = ATOMS, early: float = 0.0) -> None:
        self.unread = [i for i, a in enumerate(ATOMS) if a not in read]
        self.costs = MisplacedCosts(early)

    def target(self, start: State, goal: State) -> State:
        return target_goal(start, goal)

    def relations(self, state: State, target: State) -> tuple[tuple[Move, ...], np.ndarray]:
        rel = MoveRelations(state, target)
        bits = np.array([rel.bits(m) for m in rel.moves], np.uint8).reshape(len(rel.moves), self.width)
        bits[:, self.unread] = 0
        return rel.moves, bits

    def cover(self, bits: np.ndarray) -> Literals:
        return tuple((i, int(b)) for i, b in enumerate(bits) if i not in self.unread)


__all__ = ["GivenAtoms", "MisplacedCosts"]
