"""What LQ-CS's lifted classifiers read, and what they learn from: a vocabulary.

A **vocabulary** gives the learner (:mod:`csql_sim.learners.lifted.learner`) each move's
feature vector, the condition a new classifier is covered with, the classifiers' written
form, the target a trial plans towards and the costs its ground values learn from:

* :class:`~csql_sim.learners.lifted.given.GivenAtoms` (``features="given"``): the nine
  relations written by hand; a move no classifier matches is covered by its relations exactly;
* :class:`~csql_sim.learners.lifted.generated.GeneratedFeatures` (``features="generated"``):
  the literals of concepts the learner generates from a PDDL domain's predicates
  (:mod:`~csql_sim.learners.lifted.features`), learned from the task's reward alone.
"""

from __future__ import annotations

from collections.abc import Hashable

import numpy as np

from csql_sim.core.features.move_features import Literal
from csql_sim.core.policies.lifted_classifier import LiftedQClassifier
from csql_sim.core.state.moves import Move
from csql_sim.core.state.world import State
from csql_sim.learners.lifted.ground import Costs
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
    hand = True
    """Whether a move is a pick and a put with a held block between them (states with a held block are drawn)."""
    commits = False
    """Whether the put after a pick is the move's own (else the held state chooses it again)."""
    replay_passes = 1
    """Passes of value iteration per sweep through the model (fewer when one changes no value)."""
    costs: Costs

    def prepare(self, n: int, goals: list[State], rng: np.random.Generator) -> None:
        """Get ready for worlds of n blocks with these training goals (first met)."""

    def target(self, start: State, goal: State) -> State:
        """What a trial from ``start`` plans towards: the goal (a vocabulary may read it otherwise)."""
        return goal

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
        """A learned rule as a lifted Q-classifier line (condition over the vocabulary's features)."""
        fixed = dict(rule.literals)
        condition = "".join("#" if i not in fixed else str(fixed[i]) for i in range(self.width))
        return LiftedQClassifier(condition, rule.kind, round(rule.advantage, 3), round(rule.error, 3), rule.experience)

    def summary(self) -> tuple[tuple[Literal, ...], str, dict]:
        """What a run records of the vocabulary: its literals, its domain's text, its figures (empty: none)."""
        return (), "", {}


__all__ = ["Vocabulary"]
