"""Denotations of the grammar's nodes in a batch of states, as numpy arrays.

A concept's denotation in a batch of B (state, target) pairs over N objects is a bool array
(B, N); a role's is (B, N, N). :class:`Denotations` evaluates nodes
(:class:`~csql_sim.core.features.grammar.Node`) bottom-up and remembers each, so the
features of one batch share their sub-expressions. Transitive closures follow a functional
role (at most one successor per object, as ``on``) link by link in O(N) passes, and use
boolean matrix squaring otherwise.
"""

from __future__ import annotations

import numpy as np

from csql_sim.core.features.grammar import GrammarError, Node


class Denotations:
    """The denotations of nodes in one batch of states (primitives from :func:`primitive_arrays`).

    Args:
        prims: each predicate's extension (unary (B, N), binary (B, N, N), nullary (B,)).
        objects: N, the number of objects (blocks, then constants).
        constants: the constants' names, objects ``N - len(constants) ..``.
    """

    def __init__(self, prims: dict[str, np.ndarray], objects: int, constants: tuple[str, ...] = ()) -> None:
        self.prims, self.objects, self.constants = prims, objects, constants
        self.pairs = next(iter(prims.values())).shape[0]
        self.memo: dict[Node, np.ndarray] = {}

    def of(self, node: Node, keep: bool = True) -> np.ndarray:
        """The denotation of ``node``; remembered unless ``keep`` is False (its parts are, always)."""
        found = self.memo.get(node)
        if found is not None:
            return found
        value = self._compute(node)
        if keep:
            self.memo[node] = value
        return value

    def _compute(self, node: Node) -> np.ndarray:
        op, a = node.op, node.args
        if op == "top":
            return np.ones((self.pairs, self.objects), bool)
        if op in ("pred", "role"):
            return self._primitive(a[0], 1 if op == "pred" else 2)
        if op == "proj":
            return self._primitive(a[0], 2).any(axis=2 - a[1])
        if op == "nom":
            if a[0] not in self.constants:
                raise GrammarError(f"feature {node.text()}: {a[0]!r} is not a constant of the domain")
            out = np.zeros((self.pairs, self.objects), bool)
            out[:, self.objects - len(self.constants) + self.constants.index(a[0])] = True
            return out
        return apply(op, [self.of(x) for x in a])

    def _primitive(self, name: str, arity: int) -> np.ndarray:
        value = self.prims.get(name)
        if value is None or value.ndim != arity + 1:
            raise GrammarError(f"feature predicate {name!r}: the domain has no predicate {name}/{arity}")
        return value


def apply(op: str, args: list[np.ndarray]) -> np.ndarray:
    """A constructor applied to its arguments' denotations."""
    if op == "not":
        return ~args[0]
    if op == "and":
        return args[0] & args[1]
    if op == "some":  # some y with R(x, y) and C(y)
        return (args[0] & args[1][:, None, :]).any(axis=2)
    if op == "all":  # no y with R(x, y) outside C
        return ~(args[0] & ~args[1][:, None, :]).any(axis=2)
    if op == "eq":
        return (args[0] == args[1]).all(axis=2)
    if op == "inv":
        return args[0].transpose(0, 2, 1)
    if op in ("plus", "star"):
        out = closure(args[0])
        if op == "star":
            out = out | np.eye(out.shape[1], dtype=bool)[None]
        return out
    raise GrammarError(f"unknown constructor {op!r}")


def closure(r: np.ndarray) -> np.ndarray:
    """The transitive closure of a batch of relations (B, N, N)."""
    if (r.sum(axis=2) <= 1).all():
        return _functional_closure(r)
    if (r.sum(axis=1) <= 1).all():
        return _functional_closure(r.transpose(0, 2, 1)).transpose(0, 2, 1)
    out = r.copy()
    while True:
        step = out | (np.matmul(out.astype(np.uint8), out.astype(np.uint8)) > 0)
        if (step == out).all():
            return out
        out = step


def _functional_closure(r: np.ndarray) -> np.ndarray:
    """Closure of relations with at most one successor per object: follow the links, N passes at most."""
    b, n, _ = r.shape
    succ = np.where(r.any(axis=2), r.argmax(axis=2), -1)
    out = np.zeros_like(r)
    rows = np.arange(b)[:, None].repeat(n, 1)
    cols = np.arange(n)[None, :].repeat(b, 0)
    cur = succ
    for _ in range(n):
        live = cur >= 0
        if not live.any():
            break
        out[rows[live], cols[live], cur[live]] = True
        nxt = np.full_like(cur, -1)
        nxt[live] = succ[rows[live], cur[live]]
        cur = nxt
    return out


__all__ = ["Denotations", "apply", "closure"]
