"""Lifted Q-classifiers: conditions over the relations of a move, for any number of blocks.

A lifted Q-classifier reads the relations of a move (:mod:`csql_sim.core.state.move_relations`)
instead of a state message, so one classifier speaks of every block at once. It is
written, in the paper's style of ``#`` for don't care, as::

    Q 1110#1### move(?x,?d)->table  advantage=0.007 error=0.015 experience=4743

* the condition, one character per atom of :data:`~csql_sim.core.state.atom_names.ATOMS`
  (``misplaced(?x)``, ``goal-on(?x,?d)``, ``ready(?d)``, ``deadlocked(?x)``,
  ``above-needed(?x)``, ``least-stuck(?x)``, ``deadlock``, ``holding``, ``cover(?x)``): ``1``
  holds, ``0`` does not, ``#`` either; a file written with the first seven or eight atoms only
  is read with ``#`` for the atoms it predates;
* the action: move ``?x`` to the table (``->table``) or onto a block ``?d`` (``->block``);
* the learned **advantage**: how many moves more than the state's best move the
  classifier expects its move to cost (0: a best move), with the mean absolute error of
  that prediction and its experience (updates).

:class:`LiftedPolicy` (greedy, any n) binds ``?x`` and ``?d`` to every legal move of
the state (the held block's puts when a block is held), gives each move the advantage of
its most specific matching classifier (a default hierarchy: exceptions before the general
rule; ties, the smaller error) and takes the move of least advantage (ties, the first in
move order): with the hand empty it picks that move's block up; holding a block, it puts
it down. It is Markov: the same state and goal give the same action. The lookahead is the
one move of ``least-stuck``; nothing searches further (``cover`` is a relation of the state).
The relations are kept up to date move by move
(:class:`~csql_sim.core.state.relation_tracker.RelationTracker`), exactly the from-scratch
ones, so a plan of hundreds of blocks takes seconds.

The file (:func:`dumps_lifted_policy`) is JSON, format ``csql-sim lifted q-classifiers``,
version 1, with the atoms named, the classifiers as lines and the run's provenance.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable

import numpy as np

from csql_sim.core.classifiers.lifted_rule import read_versioned_json
from csql_sim.core.files.kinds import MAX_LIFTED_Q_BYTES
from csql_sim.core.policies.contract import Policy
from csql_sim.core.policies.lifted_classifier import (
    LIFTED_Q_FORMAT,
    LIFTED_Q_VERSION,
    MAX_CLASSIFIERS,
    LiftedPolicyError,
    LiftedQClassifier,
    classifier_lines,
    most_specific,
)
from csql_sim.core.state.atom_names import ATOMS
from csql_sim.core.state.move_relations import MoveRelations, towards
from csql_sim.core.state.moves import Move, pick_action, put_action
from csql_sim.core.state.relation_tracker import KeptRelations, RelationTracker
from csql_sim.core.state.world import TABLE, Action, State
from csql_sim.infra.files import read_text_file

_POWERS = 3 ** np.arange(len(ATOMS), dtype=np.int64)
"""A move's relations (each -1, 0 or 1) as one number: sum of (relation + 1) * 3^i (+ 3^len for a move onto a block)."""
OLDEST_ATOMS = 7
"""The fewest atoms a readable file names: files written before ``holding`` and ``cover`` are read."""


def _completions(bits: tuple[int, ...]) -> list[tuple[int, ...]]:
    """Every way of filling the unknown (-1) relations of ``bits`` with 0 or 1."""
    out = [()]
    for v in bits:
        out = [(*head, w) for head in out for w in ((0, 1) if v < 0 else (v,))]
    return out


class LiftedPolicy(Policy):
    """Greedy policy over lifted Q-classifiers, for relational states of any n (module docstring)."""

    name = "rules"
    blocks: int | None = None

    def __init__(self, classifiers: Iterable[LiftedQClassifier], meta: dict | None = None) -> None:
        self.classifiers = tuple(classifiers)
        self.meta = dict(meta or {})
        self._match: dict[tuple[tuple[int, ...], str], LiftedQClassifier | None] = {}
        self._least: dict[tuple[tuple[int, ...], str], tuple[float | None, bool]] = {}
        self._kept = KeptRelations()
        self._values: dict[tuple[tuple[int, ...], bool], tuple[float | None, bool]] = {}
        codes = 2 * 3 ** len(ATOMS)  # the numbers of :data:`_POWERS`: advantage (nan: none), doubt, known
        self._value, self._doubt, self._known = np.zeros(codes), np.zeros(codes, bool), np.zeros(codes, bool)

    def classifier_for(self, bits: tuple[int, ...], kind: str) -> LiftedQClassifier | None:
        """The most specific classifier matching a move's relations (remembered: the classifiers never change)."""
        key = (bits, kind)
        if key not in self._match:
            self._match[key] = most_specific(self.classifiers, bits, kind)
        return self._match[key]

    def least_completed(self, bits: tuple[int, ...], kind: str) -> tuple[float | None, bool]:
        """The least advantage of any matching classifier over every completion of the unknown (-1) relations.

        And whether that advantage is settled: every completion matches a classifier of that advantage,
        so the unknown relations cannot change the move's rank (no classifier that could match reads them).
        """
        key = (bits, kind)
        if key not in self._least:
            matched = [self.classifier_for(known, kind) for known in _completions(bits)]
            values = [c.advantage for c in matched if c is not None]
            least = min(values, default=None)
            self._least[key] = (least, len(values) == len(matched) and all(v == least for v in values))
        return self._least[key]

    def choose(self, relations: MoveRelations | RelationTracker) -> Move | None:
        """The move of least predicted advantage (ties: move order), or None if no classifier matches any.

        Only the first move of each class of equal block, kind and relations is looked at
        (:meth:`RelationTracker.candidates`): a later one has the same advantage, so it never wins a tie.
        ``least-stuck`` and ``cover`` are computed only when a move whose advantage depends on them could win.
        """
        if isinstance(relations, RelationTracker):
            best_of = self._best if relations.held is not None else self._best_of_arrays
            classes = relations.classes if relations.held is not None else relations.class_arrays
            for find in (relations.resolve_cover, None):  # the cover first: it is often enough to decide
                best, unsure = best_of(classes(resolve=False))
                if not unsure:
                    return best
                if find is not None:
                    find()
            return best_of(classes())[0]
        return self._best([(m.block, m.onto, bits) for m, bits in relations.candidates()])[0]

    def _best(self, candidates: list[tuple[int, int, tuple[int, ...]]]) -> tuple[Move | None, bool]:
        """The first move of least advantage; and whether a move with a relation unknown (-1) could beat it.

        ``candidates``: (block, destination, relations) in move order (:meth:`RelationTracker.classes`).
        """
        best, best_value, best_at, doubts = None, 0.0, -1, []
        values, value_of = self._values, self._value_of
        for at, (x, d, bits) in enumerate(candidates):
            key = (bits, d == TABLE)
            found = values.get(key)
            if found is None:
                found = values[key] = value_of(bits, "table" if d == TABLE else "block")
            value, doubt = found
            if doubt:
                doubts.append((at, value))
            elif value is not None and (best is None or value < best_value):
                best, best_value, best_at = (x, d), value, at
        unsure = any(best is None or value < best_value or (value == best_value and at < best_at)
                     for at, value in doubts)
        return (None if best is None else Move(*best)), unsure

    def _best_of_arrays(self, classes: tuple[np.ndarray, np.ndarray, np.ndarray]) -> tuple[Move | None, bool]:
        """:meth:`_best` over :meth:`RelationTracker.class_arrays` (blocks, destinations, relations).

        Each move's relations are one number (:data:`_POWERS`), its advantage and doubt looked up in
        arrays filled from :meth:`_value_of` the first time a number is met.
        """
        xs, ds, bits = classes
        code = (bits.astype(np.int64) + 1) @ _POWERS + (ds != TABLE) * (3 * _POWERS[-1])
        if not self._known[code].all():
            for c in np.unique(code[~self._known[code]]).tolist():
                at = int(np.flatnonzero(code == c)[0])
                value, doubt = self._value_of(tuple(bits[at].tolist()), "table" if ds[at] == TABLE else "block")
                self._value[c], self._doubt[c], self._known[c] = np.nan if value is None else value, doubt, True
        value, doubt = self._value[code], self._doubt[code]
        ranked = np.where(doubt | np.isnan(value), np.inf, value)
        at = int(np.argmin(ranked)) if len(ranked) else 0
        if not len(ranked) or ranked[at] == np.inf:
            return None, bool(doubt.any())
        rival = value[doubt]
        unsure = bool(((rival < ranked[at]) | ((rival == ranked[at]) & (np.flatnonzero(doubt) < at))).any())
        return Move(int(xs[at]), int(ds[at])), unsure

    def _value_of(self, bits: tuple[int, ...], kind: str) -> tuple[float | None, bool]:
        """A move's advantage (None: no classifier matches), and whether its unknown relations could lower it."""
        if -1 in bits:
            least, settled = self.least_completed(bits, kind)
            return least, least is not None and not settled
        c = self.classifier_for(bits, kind)
        return (None if c is None else c.advantage), False

    def act(self, state: State, goal: State) -> Action | None:
        """The next action towards ``goal``: None at the goal or when no classifier matches."""
        target, last = towards(state, goal)
        if target is None:
            return last
        move = self.choose(self.relations(state, target))
        if move is None:
            return None
        action = put_action(move) if state.held is not None else pick_action(state, move.block)
        self._kept.chose(action)
        return action

    def relations(self, state: State, target: State) -> RelationTracker:
        """The move relations of ``state`` towards ``target``, kept from the last call.

        They are the last state's, updated by the action chosen there, when ``state`` is where it
        leads; else they are computed from scratch.

        Either way they are exactly the relations of ``state`` (a cache of derived facts, not a
        memory of visited states: the same state gives the same action).
        """
        return self._kept.of(state, target)


# ---------------------------------------------------------------- the file


def dumps_lifted_policy(classifiers: Iterable[LiftedQClassifier], meta: dict) -> str:
    """The file's text: JSON with the format, version, atoms, ``meta`` and one line per classifier."""
    doc = {"format": LIFTED_Q_FORMAT, "version": LIFTED_Q_VERSION, "atoms": list(ATOMS), "meta": meta,
           "classifiers": [c.text() for c in classifiers]}
    return json.dumps(doc, indent=2) + "\n"


def loads_lifted_policy(text: str, source: str = "lifted Q-classifier file") -> LiftedPolicy:
    """The policy of a file's text; raises LiftedPolicyError naming the source and what is wrong."""
    doc = read_versioned_json(text, source, LIFTED_Q_FORMAT, LIFTED_Q_VERSION, LiftedPolicyError)
    if "domain" in doc:
        raise LiftedPolicyError(f"{source} holds classifiers over generated features: read it with "
                                "csql_sim.core.policies.loader.load_policy")
    atoms = doc.get("atoms")
    if not isinstance(atoms, list) or atoms != list(ATOMS[:len(atoms)]) or len(atoms) < OLDEST_ATOMS:
        raise LiftedPolicyError(f"{source} names other atoms than this csql-sim's {', '.join(ATOMS)}")
    pad = "#" * (len(ATOMS) - len(atoms))  # a file written before ``holding`` or ``cover``: either value
    lines, meta = doc.get("classifiers"), doc.get("meta", {})
    if not isinstance(lines, list) or not all(isinstance(x, str) for x in lines) or not isinstance(meta, dict):
        raise LiftedPolicyError(f"{source}: 'classifiers' must be a list of lines and 'meta' an object")
    if not 0 < len(lines) <= MAX_CLASSIFIERS:
        raise LiftedPolicyError(f"{source} holds {len(lines)} classifiers; expected 1..{MAX_CLASSIFIERS}")
    classifiers = classifier_lines(lines, source, len(ATOMS), pad)
    return LiftedPolicy(classifiers, meta)


def load_lifted_policy(path: str | os.PathLike) -> LiftedPolicy:
    """Read a lifted Q-classifier file (regular file, size-capped)."""
    text = read_text_file(path, MAX_LIFTED_Q_BYTES, "lifted Q-classifier file")
    return loads_lifted_policy(text, f"lifted Q-classifier file {os.fspath(path)!r}")


__all__ = ["LiftedPolicy", "dumps_lifted_policy", "load_lifted_policy", "loads_lifted_policy"]
