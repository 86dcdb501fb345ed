"""What LQ-CS's lifted classifiers read: the given atoms, or features generated from the domain's predicates.

A **vocabulary** gives the learner each move's feature vector, the condition a new classifier
is covered with, and the classifiers' written form:

* :class:`GivenAtoms` (``features="given"``): the nine relations written by hand
  (:data:`~csql_sim.core.state.move_relations.ATOMS`); a move no classifier matches is
  covered by its relations exactly;
* :class:`GeneratedFeatures` (``features="generated"``): the literals of concepts the learner
  generates from a PDDL domain's predicates (:mod:`~csql_sim.learners.lifted.features`);
  with thousands of them an exact cover would never generalize, so the cover is the most
  general classifier of the move's kind, and specialization chooses the features.
"""

from __future__ import annotations

from collections.abc import Hashable

import numpy as np

from csql_sim.core.features.formulation import Formulation
from csql_sim.core.features.move_features import Literal
from csql_sim.core.policies.lifted_policy import LiftedQClassifier
from csql_sim.core.state.move_relations import ATOMS, MoveRelations
from csql_sim.core.state.moves import Move
from csql_sim.core.state.world import State
from csql_sim.learners.lifted.features import FeatureSpace, FeatureTable, build_space
from csql_sim.learners.lifted.rules import Literals, Rule


class Vocabulary:
    """The features a learner's classifiers read (module docstring)."""

    name = "vocabulary"
    width = 0
    cache_relations = True
    warmup = 0
    """Sweeps before the first specialization."""
    fresh_stats = False
    """Whether the split statistics restart at every sweep (they then read the values of the last sweep's trials)."""

    def prepare(self, n: int, goals: list[State], rng: np.random.Generator) -> None:
        """Get ready for worlds of n blocks with these training goals (first met)."""

    def relations(self, state: State, target: State) -> tuple[tuple[Move, ...], np.ndarray]:
        """The legal moves of ``state`` and their feature vectors (moves, width), uint8."""
        raise NotImplementedError

    def cover(self, bits: np.ndarray) -> Literals:
        """The condition of a classifier covering a move with feature vector ``bits``."""
        raise NotImplementedError

    def match_key(self, i: int, j: int, bits: np.ndarray, kind: str) -> Hashable:
        """What the match of move j of ground state i is remembered by until the next sweep."""
        return bits.tobytes(), kind

    def classifier(self, rule: Rule) -> LiftedQClassifier:
        """A learned rule as a lifted Q-classifier line (condition over :meth:`atoms`)."""
        fixed = dict(rule.literals)
        condition = "".join("#" if i not in fixed else str(fixed[i]) for i in range(self.width))
        return LiftedQClassifier(condition, rule.kind, round(rule.advantage, 3), round(rule.error, 3), rule.experience)


class GivenAtoms(Vocabulary):
    """The nine relations of a move written by hand (:data:`ATOMS`), of which the classifiers read ``read``.

    An atom not read is 0 in every feature vector and left out of every cover, so it is ``#`` in
    every condition and no split can choose it.
    """

    name = "given"
    width = len(ATOMS)

    def __init__(self, read: tuple[str, ...] = ATOMS) -> None:
        self.unread = [i for i, a in enumerate(ATOMS) if a not in read]

    def relations(self, state: State, target: State) -> tuple[tuple[Move, ...], np.ndarray]:
        rel = MoveRelations(state, target)
        bits = np.array([rel.bits(m) for m in rel.moves], np.uint8).reshape(len(rel.moves), self.width)
        bits[:, self.unread] = 0
        return rel.moves, bits

    def cover(self, bits: np.ndarray) -> Literals:
        return tuple((i, int(b)) for i, b in enumerate(bits) if i not in self.unread)


class GeneratedFeatures(Vocabulary):
    """Literals of concepts generated from a formulation's predicates, within complexity ``complexity``."""

    name = "generated"
    cache_relations = False
    warmup = 3
    fresh_stats = True

    def __init__(self, form: Formulation, domain: str, complexity: int, sample: int) -> None:
        self.form, self.domain, self.complexity, self.sample = form, domain, complexity, sample
        self.space: FeatureSpace | None = None
        self.tables: dict[int, FeatureTable] = {}

    def prepare(self, n: int, goals: list[State], rng: np.random.Generator) -> None:
        """Build the feature space on the first world met; table every world's pairs."""
        if not self.form.hand:
            goals = [g for g in goals if g.held is None] or goals
        if self.space is None:
            self.space = build_space(self.form, n, goals, rng, self.complexity, self.sample)
            self.width = len(self.space.literals)
        self.tables[n] = FeatureTable(self.space, n, goals)

    @property
    def literals(self) -> tuple[Literal, ...]:
        """The literals of the feature space (empty before :meth:`prepare`)."""
        return () if self.space is None else self.space.literals

    def relations(self, state: State, target: State) -> tuple[tuple[Move, ...], np.ndarray]:
        return self.tables[state.n].relations(state, target)

    def cover(self, bits: np.ndarray) -> Literals:
        return ()

    def match_key(self, i: int, j: int, bits: np.ndarray, kind: str) -> Hashable:
        return i, j


__all__ = ["GeneratedFeatures", "GivenAtoms", "Vocabulary"]
