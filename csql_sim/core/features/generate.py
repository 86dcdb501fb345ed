"""Generating the grammar's concepts up to a complexity bound, pruned by their denotations.

:func:`generate_concepts` enumerates concepts and roles (:mod:`~csql_sim.core.features.grammar`)
by complexity 1, 2, ..., K over a formulation's predicates, as ``dlplan``'s generator does:

* primitives: ``top``, every unary predicate, both projections of every binary one, the
  nominals of the constants; roles: every binary predicate;
* each level applies every constructor to the kept nodes whose complexities add up to one
  less: ``not``, ``and``, ``some``, ``all``, ``eq``; ``inv``, ``plus``, ``star``;
* a node whose denotation on the sample states equals that of a node already kept is
  dropped (the simpler one, found first, stays), and so is a concept empty in every sample
  state or holding every object in every one: a feature with the same value on all
  training states tells nothing.

The kept concepts are the **features**: for a move, whether ``?x`` and ``?d`` belong to
them, before and after the move, and how the move changes their counts ``|C|``
(:mod:`~csql_sim.core.features.move_features`).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np

from csql_sim.core.features.denotation import Denotations, apply
from csql_sim.core.features.formulation import Formulation
from csql_sim.core.features.grammar import TOP, Node, pred, role

DEFAULT_COMPLEXITY = 8
"""The grammar's complexity bound K."""


@dataclass(frozen=True)
class GeneratedPool:
    """What :func:`generate_concepts` kept.

    Attributes:
        concepts: the feature concepts, by complexity then order found.
        roles: the roles kept (building blocks).
        candidates: nodes evaluated; duplicates: dropped as equal to a kept one; constant: dropped as constant.
    """

    concepts: tuple[Node, ...]
    roles: tuple[Node, ...]
    candidates: int
    duplicates: int
    constant: int


class _Pool:
    def __init__(self, den: Denotations) -> None:
        self.den = den
        self.seen: set[bytes] = set()
        self.concepts: dict[int, list[Node]] = {}
        self.roles: dict[int, list[Node]] = {}
        self.features: list[Node] = []
        self.candidates = self.duplicates = self.constant = 0

    def offer(self, node: Node, value: np.ndarray) -> None:
        self.candidates += 1
        key = (b"r" if node.is_role else b"c") + hashlib.blake2b(np.packbits(value).tobytes(), digest_size=16).digest()
        if key in self.seen:
            self.duplicates += 1
            return
        self.seen.add(key)
        self.den.memo[node] = value
        (self.roles if node.is_role else self.concepts).setdefault(node.complexity, []).append(node)
        if not node.is_role:
            per_state = value.any(axis=1), value.all(axis=1)
            if not per_state[0].any() or per_state[1].all():
                self.constant += 1
            else:
                self.features.append(node)


def generate_concepts(form: Formulation, den: Denotations, max_complexity: int = DEFAULT_COMPLEXITY
                      ) -> GeneratedPool:
    """Every concept up to ``max_complexity``, pruned by denotation on the states of ``den`` (module docstring)."""
    pool = _Pool(den)
    for node in _primitives(form):
        pool.offer(node, den.of(node, keep=False))
    for k in range(2, max_complexity + 1):
        for op, args in _combinations(pool, k):
            node = Node(op, args)
            pool.offer(node, apply(op, [den.of(a) for a in args]))
    roles = tuple(r for k in sorted(pool.roles) for r in pool.roles[k])
    return GeneratedPool(tuple(pool.features), roles, pool.candidates, pool.duplicates, pool.constant)


def _primitives(form: Formulation) -> list[Node]:
    out = [TOP]
    for p in form.predicates:
        if p.arity == 1:
            out.append(pred(p.name))
        elif p.arity == 2:
            out += [Node("proj", (p.name, 0)), Node("proj", (p.name, 1)), role(p.name)]
    out += [Node("nom", (c,)) for c in form.constants]
    return out


def _combinations(pool: _Pool, k: int):  # noqa: ANN202 - a generator of (op, args)
    """Every constructor over kept nodes whose complexities sum to k - 1 (no double inverse, negation, closure)."""
    c, r = pool.concepts, pool.roles
    for x in r.get(k - 1, []):
        if x.op != "inv":
            yield "inv", (x,)
        if x.op not in ("plus", "star"):
            yield "plus", (x,)
            yield "star", (x,)
    for x in c.get(k - 1, []):
        if x.op != "not":
            yield "not", (x,)
    for i in range(1, k - 1):
        for x in r.get(i, []):
            for y in c.get(k - 1 - i, []):
                yield "some", (x, y)
                yield "all", (x, y)
        for x in r.get(i, []):
            for y in r.get(k - 1 - i, []):
                if i < k - 1 - i or (i == k - 1 - i and x.text() < y.text()):
                    yield "eq", (x, y)
        for x in c.get(i, []):
            for y in c.get(k - 1 - i, []):
                if i < k - 1 - i or (i == k - 1 - i and x.text() < y.text()):
                    yield "and", (x, y)


__all__ = ["DEFAULT_COMPLEXITY", "GeneratedPool", "generate_concepts"]
