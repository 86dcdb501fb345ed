"""The generated features LQ-CS learns over: built from the domain's predicates, tabled for the training worlds.

:func:`build_space` is the learner's feature construction, from its own training worlds:

1. it samples ``sample`` (state, goal) pairs of the training worlds with the run's generator,
   and adds the state after every legal move of each (one move of lookahead);
2. it generates every concept of the formulation's grammar up to the complexity bound on
   those states (:func:`~csql_sim.core.features.generate.generate_concepts`), dropping
   concepts equal to a simpler one there;
3. it keeps the move literals (:mod:`~csql_sim.core.features.move_features`) that differ
   from every simpler literal, and from a constant, on the sampled moves.

:class:`FeatureTable` holds the kept concepts' denotations in every (state, goal) pair of one
training world size, packed one byte per concept (a bit per object), so a move's literals
are a few array lookups.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np

from csql_sim.core.features.denotation import Denotations
from csql_sim.core.features.formulation import Formulation, primitive_arrays
from csql_sim.core.features.generate import BASE, generate_concepts
from csql_sim.core.features.move_features import HOLDS, SLOTS, Literal, object_of, parsed
from csql_sim.core.state.moves import Move, after, moves
from csql_sim.core.state.world import State, all_states
from csql_sim.learners.lifted.potential import Potential, fit_potential, state_values

MAX_TABLE_OBJECTS = 8
"""A packed denotation holds one bit per object: at most 8 (5 blocks and the table)."""


@dataclass(frozen=True)
class FeatureSpace:
    """The literals a learner chooses among, and what building them found.

    Attributes:
        form: the formulation whose predicates the features read.
        literals: the kept move literals, by concept complexity then slot.
        concepts: the kept concepts' texts, in the order of their first literal.
        generated: concepts generated (after pruning equal denotations); candidates: nodes evaluated.
        complexity: the bound K.
        potential: the count fitted to the moves left (:mod:`~csql_sim.learners.lifted.potential`), or None.
    """

    form: Formulation
    literals: tuple[Literal, ...]
    concepts: tuple[str, ...]
    generated: int
    candidates: int
    complexity: int
    potential: Potential | None = None


def training_states(form: Formulation, n: int) -> list[State]:
    """Every state of the n-block world the formulation has (no held block without a hand)."""
    return [s for s in all_states(n) if form.hand or s.held is None]


def build_space(form: Formulation, n: int, goals: list[State], rng: np.random.Generator,
                complexity: int, sample: int = 200, constructors: tuple[str, ...] = BASE,
                fit: bool = False) -> FeatureSpace:
    """The feature space of a training world (module docstring); with ``fit``, its potential too."""
    states = training_states(form, n)
    picked = [(states[int(rng.integers(len(states)))], goals[int(rng.integers(len(goals)))]) for _ in range(sample)]
    batch_s, batch_t, owner, succ, xs, ds = [], [], [], [], [], []
    for s, t in picked:
        owner_row = len(batch_s)
        batch_s.append(s)
        batch_t.append(t)
        for m in moves(s):
            owner.append(owner_row)
            succ.append(len(batch_s))
            xs.append(m.block)
            ds.append(object_of(s, form, m.onto))
            batch_s.append(after(s, m))
            batch_t.append(t)
    prims, objects = primitive_arrays(form, batch_s, batch_t)
    den = Denotations(prims, objects, form.constants)
    pool = generate_concepts(form, den, complexity, constructors)
    cols = _MoveColumns(np.array(owner), np.array(succ), np.array(xs), np.array(ds))
    seen: set[bytes] = set()
    literals: list[Literal] = []
    for name, value in prims.items():
        if value.ndim == 1:
            _keep(Literal(name, HOLDS), value[cols.owner], seen, literals)
    for concept in pool.concepts:
        c = den.of(concept)
        for slot in SLOTS:
            _keep(Literal(concept.text(), slot), cols.values(slot, c), seen, literals)
    concepts = tuple(dict.fromkeys(lit.feature for lit in literals if lit.slot != HOLDS))
    potential = _fitted(pool.concepts, den, states, batch_s, batch_t) if fit else None
    return FeatureSpace(form, tuple(literals), concepts, len(pool.concepts), pool.candidates, complexity, potential)


def _fitted(concepts: tuple, den: Denotations, states: list[State], batch_s: list[State], batch_t: list[State]
            ) -> Potential | None:
    """The potential fitted on the batch's hand-empty pairs, their moves left by value iteration."""
    values = state_values(states, batch_t)
    rows = [k for k, pair in enumerate(zip(batch_s, batch_t, strict=True)) if pair in values]
    return fit_potential(concepts, den, np.array(rows, np.int64),
                         np.array([values[(batch_s[k], batch_t[k])] for k in rows]))


@dataclass(frozen=True)
class _MoveColumns:
    owner: np.ndarray
    succ: np.ndarray
    xs: np.ndarray
    ds: np.ndarray

    def values(self, slot: str, c: np.ndarray) -> np.ndarray:
        """A slot's values on the sampled moves, from a concept's denotation (batch, objects)."""
        now, nxt = c[self.owner], c[self.succ]
        rows = np.arange(len(self.owner))
        if slot == "x":
            return now[rows, self.xs]
        if slot == "d":
            return np.where(self.ds >= 0, now[rows, np.maximum(self.ds, 0)], False)
        if slot == "x'":
            return nxt[rows, self.xs]
        count, counts = now.sum(axis=1), nxt.sum(axis=1)
        return {"down": counts < count, "up": counts > count, "any": count > 0}[slot]


def _keep(lit: Literal, column: np.ndarray, seen: set[bytes], out: list[Literal]) -> None:
    column = column.astype(bool)
    if column.all() or not column.any():
        return
    key = hashlib.blake2b(np.packbits(column).tobytes(), digest_size=16).digest()
    if key not in seen:
        seen.add(key)
        out.append(lit)


class FeatureTable:
    """The kept concepts' denotations in every (state, goal) pair of one training world, packed.

    ``relations(state, target)`` gives the legal moves and their literal values (moves,
    literals) as uint8, the same values :func:`~csql_sim.core.features.move_features.literal_values`
    computes from scratch.
    """

    def __init__(self, space: FeatureSpace, n: int, goals: list[State], chunk: int = 4096) -> None:
        form = space.form
        self.space, self.form = space, form
        states = training_states(form, n)
        targets = dict.fromkeys(goals)  # as they are: a goal that holds a block too
        self.index = {(s, t): i for i, (s, t) in enumerate((s, t) for t in targets for s in states)}
        pairs = list(self.index)
        objects = n + len(form.constants)
        if objects > MAX_TABLE_OBJECTS:
            raise ValueError(f"a feature table holds at most {MAX_TABLE_OBJECTS} objects, not {objects}")
        tabled = list(space.concepts)
        if space.potential is not None and space.potential.concept not in concept_at_of(tabled):
            tabled.append(space.potential.concept)
        concept_at = concept_at_of(tabled)
        self.potential_at = None if space.potential is None else concept_at[space.potential.concept]
        self.packed = np.zeros((len(pairs), len(tabled)), np.uint8)
        self.holds = [k for k, lit in enumerate(space.literals) if lit.slot == HOLDS]
        self.nullary = np.zeros((len(pairs), len(self.holds)), np.uint8)
        weights = (1 << np.arange(objects)).astype(np.uint16)
        for lo in range(0, len(pairs), chunk):
            part = pairs[lo:lo + chunk]
            prims, _ = primitive_arrays(form, [s for s, _ in part], [t for _, t in part])
            den = Denotations(prims, objects, form.constants)
            for text, j in concept_at.items():
                self.packed[lo:lo + len(part), j] = (den.of(parsed(text)) @ weights).astype(np.uint8)
            for k, at in enumerate(self.holds):
                self.nullary[lo:lo + len(part), k] = prims[space.literals[at].feature]
        slot_of = [SLOTS.index(lit.slot) if lit.slot in SLOTS else -1 for lit in space.literals]
        self.by_slot = [(np.array([k for k, v in enumerate(slot_of) if v == j], np.int64),) for j in range(len(SLOTS))]
        self.by_slot = [(cols, np.array([concept_at[space.literals[k].feature] for k in cols], np.int64))
                        for (cols,) in self.by_slot]

    def estimate(self, state: State, target: State) -> float:
        """The space's potential h of (state, target): its fitted estimate of the moves left."""
        if self.potential_at is None or self.space.potential is None:
            raise ValueError("this feature space has no potential")
        return float(self.space.potential.of(int(_POPCOUNT[self.packed[self.index[(state, target)],
                                                                        self.potential_at]])))

    def relations(self, state: State, target: State) -> tuple[tuple[Move, ...], np.ndarray]:
        """The legal moves of ``state`` and their literals' values (moves, literals)."""
        i = self.index[(state, target)]
        options = moves(state)
        nxt = np.array([self.index[(after(state, m), target)] for m in options])
        xs = np.array([m.block for m in options])[:, None]
        ds = np.array([object_of(state, self.form, m.onto) for m in options])[:, None]
        out = np.zeros((len(options), len(self.space.literals)), np.uint8)
        for slot, (cols, c) in zip(SLOTS, self.by_slot, strict=True):
            if not len(cols):
                continue
            if slot in ("x", "d", "x'"):
                packed = self.packed[nxt][:, c] if slot == "x'" else self.packed[i, c][None, :]
                at = ds if slot == "d" else xs
                bits = (packed >> np.maximum(at, 0)) & 1
                out[:, cols] = np.where(at >= 0, bits, 0) if slot == "d" else bits
                continue
            count, counts = _POPCOUNT[self.packed[i, c]][None, :], _POPCOUNT[self.packed[nxt][:, c]]
            out[:, cols] = {"down": counts < count, "up": counts > count}.get(slot, count > 0)
        out[:, self.holds] = self.nullary[i][None, :]
        return options, out


_POPCOUNT = np.array([bin(v).count("1") for v in range(256)], np.uint8)


def concept_at_of(texts: list[str]) -> dict[str, int]:
    """Each concept's column."""
    return {text: j for j, text in enumerate(texts)}


__all__ = ["FeatureSpace", "FeatureTable", "build_space", "training_states"]
