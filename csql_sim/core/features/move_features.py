"""The features of a move: what a lifted classifier over generated features reads.

A move binds ``?x`` (the block moved) and ``?d`` (where it goes), from a state s to the
hand-empty state s' after it (:func:`~csql_sim.core.state.moves.after`: one move
of lookahead through the world model). For every feature concept C
(:mod:`~csql_sim.core.features.generate`) a move has six **literals** (:data:`SLOTS`):

============  ====================================================================
``x``         ?x ∈ C in s
``d``         ?d ∈ C in s (0 when ?d is the table and the table is not an object)
``x'``        ?x ∈ C in s' (after the move)
``down``      |C| is smaller in s' than in s
``up``        |C| is larger in s' than in s
``any``       |C| > 0 in s (a condition of the state)
============  ====================================================================

and every nullary predicate p (``handempty``) has one, ``holds``: p is true in s.

A :class:`FeatureSpace` is the list of literals a learner chooses among: the concepts
generated within the complexity bound, less the literals that take the same values as a
simpler one on every sampled training move (or one value on all of them).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from csql_sim.core.features.denotation import Denotations
from csql_sim.core.features.formulation import Formulation, support_arrays
from csql_sim.core.features.grammar import Node, parse
from csql_sim.core.state.moves import Move, moves
from csql_sim.core.state.world import TABLE, State

SLOTS = ("x", "d", "x'", "down", "up", "any")
"""The literals of a concept, in column order."""
HOLDS = "holds"
"""The literal of a nullary predicate."""
AFTER = ("x'", "down", "up")
"""The slots read in the state after the move."""


@dataclass(frozen=True)
class Literal:
    """One column of a move's features: a concept (or nullary predicate) and a slot."""

    feature: str
    slot: str

    def text(self) -> str:
        """``[x ∈ C]``-style, with the concept written (:meth:`Node.text`)."""
        return f"{self.slot}:{self.feature}"

    def words(self) -> str:
        """The literal in description-logic notation."""
        if self.slot == HOLDS:
            return self.feature
        c = parsed(self.feature).words()
        forms = {"x": f"?x ∈ {c}", "d": f"?d ∈ {c}", "x'": f"?x ∈ {c} after", "down": f"|{c}| falls",
                 "up": f"|{c}| rises", "any": f"|{c}| > 0"}
        return forms[self.slot]


def parse_literal(text: str) -> Literal:
    """A literal from :meth:`Literal.text`."""
    slot, _, feature = text.partition(":")
    if slot not in (*SLOTS, HOLDS) or not feature:
        raise ValueError(f"literal {text[:80]!r}: expected SLOT:FEATURE with SLOT one of {', '.join((*SLOTS, HOLDS))}")
    if slot != HOLDS:
        parsed(feature)
    return Literal(feature, slot)


def object_of(state: State, form: Formulation, d: int) -> int:
    """The object index of a move's destination: the block, the table object, or -1 (no table object)."""
    if d != TABLE:
        return d
    return state.n + form.constants.index("table") if form.table_object else -1


def literal_values(literals: tuple[Literal, ...], form: Formulation, state: State, target: State,
                   options: tuple[Move, ...] | None = None) -> tuple[tuple[Move, ...], np.ndarray]:
    """The legal moves of ``state`` (or ``options``) and their literals' values (moves, literals), uint8.

    A concept read only in the state (slots ``x``, ``d``, ``any``) is evaluated there; one read
    after the moves too (``x'``, ``down``, ``up``), once on the batch of the state and every
    state after a move.
    """
    options = moves(state) if options is None else options
    xs = np.array([m.block for m in options], np.int64)
    ds = np.array([object_of(state, form, m.onto) for m in options], np.int64)
    later = any(lit.slot in AFTER for lit in literals)
    sup = np.tile(np.array(state.support, np.int64), (len(options) + 1 if later else 1, 1))
    if later:
        sup[np.arange(1, len(options) + 1), xs] = [m.onto for m in options]  # the states after the moves
    prims, objects = support_arrays(form, sup, np.array([target.support], np.int64))  # the goal's: one row
    den = Denotations(prims, objects, form.constants)
    now_only = Denotations({k: v[:1] for k, v in prims.items()}, objects, form.constants)
    out = np.zeros((len(options), len(literals)), np.uint8)
    rows = np.arange(len(options))
    for j, lit in enumerate(literals):
        if lit.slot == HOLDS:
            out[:, j] = prims[lit.feature][0]
            continue
        c = (den if lit.slot in AFTER else now_only).of(parsed(lit.feature))
        out[:, j] = _slot(lit.slot, c[0], c[1:], rows, xs, ds)
    return options, out


def _slot(slot: str, now: np.ndarray, nxt: np.ndarray, rows: np.ndarray, xs: np.ndarray, ds: np.ndarray
          ) -> np.ndarray:
    """One slot's values for every move, from the concept in s (``now``, (N,)) and in each s' (``nxt``, (M, N))."""
    if slot == "x":
        return now[xs]
    if slot == "d":
        return np.where(ds >= 0, now[np.maximum(ds, 0)], False)
    if slot == "x'":
        return nxt[rows, xs]
    count, counts = now.sum(), nxt.sum(axis=1)
    if slot == "down":
        return counts < count
    if slot == "up":
        return counts > count
    return np.full(len(xs), count > 0)


@functools.lru_cache(maxsize=1 << 16)
def parsed(text: str) -> Node:
    """:func:`parse`, remembered (nodes are immutable)."""
    return parse(text)


def concept_of(lit: Literal) -> Node | None:
    """The literal's concept (None for a nullary predicate)."""
    return None if lit.slot == HOLDS else parsed(lit.feature)


__all__ = ["HOLDS", "SLOTS", "Literal", "concept_of", "literal_values", "object_of", "parse_literal", "parsed"]
