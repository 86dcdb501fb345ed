"""Denotations of the grammar's nodes in a batch of states, as numpy arrays.

A concept's denotation in a batch of B (state, target) pairs over N objects is a bool array
(B, N); a role's is (B, N, N). :class:`Denotations` evaluates nodes
(:class:`~csql_sim.core.features.grammar.Node`) bottom-up and remembers each, so the
features of one batch share their sub-expressions. Transitive closures follow a functional
role (at most one successor per object, as ``on``) link by link in O(N) passes, and use
boolean matrix squaring otherwise.

A planner's batch is one state and the state after each of its moves, towards one goal: the
goal's predicates are given once (one row), so what is built from them alone is evaluated
once; ``∃R.C`` over a primitive role follows its links instead of testing every pair; and
``(R⁻¹)⁺`` and ``R*`` reuse ``R⁺``. Each shortcut equals the definition (:func:`apply`).
"""

from __future__ import annotations

import numpy as np

from csql_sim.core.features.grammar import GrammarError, Node


class Denotations:
    """The denotations of nodes in one batch of states (primitives from :func:`primitive_arrays`).

    A primitive given with one row (a goal predicate, the same in every pair of the batch) keeps
    one row, and so does every node built from such primitives alone: :meth:`of` broadcasts it
    to the batch. ``∃R.C`` and ``∀R.C`` over such a role are one matrix product; over a role with
    at most one successor (or predecessor) per object they gather (or scatter) along its links.

    Args:
        prims: each predicate's extension (unary (B, N), binary (B, N, N), nullary (B,)), or one row of it.
        objects: N, the number of objects (blocks, then constants).
        constants: the constants' names, objects ``N - len(constants) ..``.
    """

    def __init__(self, prims: dict[str, np.ndarray], objects: int, constants: tuple[str, ...] = ()) -> None:
        self.prims, self.objects, self.constants = prims, objects, constants
        self.pairs = max(v.shape[0] for v in prims.values())
        self.memo: dict[Node, np.ndarray] = {}
        self._links: dict[Node, tuple[np.ndarray | None, np.ndarray | None]] = {}

    def of(self, node: Node, keep: bool = True) -> np.ndarray:
        """The denotation of ``node`` in every pair; remembered unless ``keep`` is False (its parts are, always)."""
        value = self._of(node, keep)
        return value if value.shape[0] == self.pairs else np.broadcast_to(value, (self.pairs, *value.shape[1:]))

    def _of(self, node: Node, keep: bool = True) -> np.ndarray:
        found = self.memo.get(node)
        if found is not None:
            return found
        value = self._compute(node)
        if keep:
            self.memo[node] = value
        return value

    def count(self, node: Node) -> np.ndarray:
        """The numerical feature of ``node`` in every pair: ``|C|`` of a concept, ``|R|`` of a role (pairs,)."""
        value = self.of(node)
        return value.reshape(value.shape[0], -1).sum(axis=1)

    def _compute(self, node: Node) -> np.ndarray:
        op, a = node.op, node.args
        if op == "top":
            return np.ones((1, self.objects), bool)
        if op in ("pred", "role"):
            return self._primitive(a[0], 1 if op == "pred" else 2)
        if op == "proj":
            return self._primitive(a[0], 2).any(axis=2 - a[1])
        if op == "nom":
            if a[0] not in self.constants:
                raise GrammarError(f"feature {node.text()}: {a[0]!r} is not a constant of the domain")
            out = np.zeros((1, self.objects), bool)
            out[:, self.objects - len(self.constants) + self.constants.index(a[0])] = True
            return out
        if op in ("some", "all"):
            return self._quantified(op, a[0], self._of(a[1]))
        if op in ("plus", "star"):
            return self._closure(op, a[0])
        if op == "eq" and all(x.op in ("role", "inv") for x in a):
            links = [self._successors(x) for x in a]
            if links[0] is not None and links[1] is not None:  # one successor or none each: the same one
                return links[0] == links[1]
        return apply(op, [self._of(x) for x in a])

    def _successors(self, node: Node) -> np.ndarray | None:
        """Each object's one successor under a primitive role or its inverse (-1: none), or None if some has two."""
        role = self._of(node)
        return _index(role, 2) if role.shape[0] == 1 else self._links_of(node, role)[0]

    def _quantified(self, op: str, r: Node, c: np.ndarray) -> np.ndarray:
        """∃R.C or ∀R.C (∀R.C is ¬∃R.¬C), by the cheapest of a product, a gather, a scatter or the definition."""
        c = c if op == "some" else ~c
        if r.op in ("plus", "star") and r.args[0].op in ("role", "inv"):
            succ, _ = self._links_of(r.args[0], self._of(r.args[0]))
            if succ is not None:  # along the links: the closure itself is never built
                found = chain_any(c, succ, r.op == "star")
                return found if op == "some" else ~found
        role = self._of(r)
        succ, pred_ = self._links_of(r, role)
        if role.shape[0] == 1:
            found = (c.astype(np.float32) @ role[0].T.astype(np.float32)) > 0
        elif succ is not None:
            found = np.where(succ >= 0, c[np.arange(c.shape[0])[:, None] if c.shape[0] > 1 else 0,
                                          np.maximum(succ, 0)], False)
        elif pred_ is not None:
            found = np.zeros((self.pairs, self.objects), bool)
            rows, ys = np.nonzero((pred_ >= 0) & c)
            found[rows, pred_[rows, ys]] = True
        else:
            found = (role & c[:, None, :]).any(axis=2)
        return found if op == "some" else ~found

    def _links_of(self, node: Node, role: np.ndarray) -> tuple[np.ndarray | None, np.ndarray | None]:
        """A primitive role's (or its inverse's) successor and predecessor indexes (B, N), -1 for none.

        Each is None where some object has two, or the role is one row (the product is cheaper).
        """
        if node.op not in ("role", "inv") or role.shape[0] == 1:
            return None, None
        if node not in self._links:
            if node.op == "inv":
                succ, pred_ = self._links_of(node.args[0], self._of(node.args[0]))
                self._links[node] = (pred_, succ)
            else:
                self._links[node] = (_index(role, 2), _index(role, 1))
        return self._links[node]

    def _closure(self, op: str, r: Node) -> np.ndarray:
        """R⁺ (one closure per role: (R⁻¹)⁺ is (R⁺)⁻¹) and R* = R⁺ ∪ identity."""
        if r.op == "inv":
            return self._of(Node(op, r.args)).transpose(0, 2, 1)
        if op == "star":
            return self._of(Node("plus", (r,))) | np.eye(self.objects, dtype=bool)[None]
        role = self._of(r)
        return closure(role, *self._links_of(r, role))

    def _primitive(self, name: str, arity: int) -> np.ndarray:
        value = self.prims.get(name)
        if value is None or value.ndim != arity + 1:
            raise GrammarError(f"feature predicate {name!r}: the domain has no predicate {name}/{arity}")
        return value


def _index(role: np.ndarray, axis: int) -> np.ndarray | None:
    """Along ``axis`` (2: successors, 1: predecessors) each object's one partner, -1 for none; None if some has two."""
    partnered = role.any(axis=axis)
    if np.count_nonzero(role) != np.count_nonzero(partnered):  # some object has two partners
        return None
    return np.where(partnered, role.argmax(axis=axis), -1)


def by_definition(node: Node, prims: dict[str, np.ndarray], objects: int, constants: tuple[str, ...] = (),
                  memo: dict[Node, np.ndarray] | None = None) -> np.ndarray:
    """A node's denotation from the grammar's definitions alone (:func:`apply`), primitives given in full.

    The reference that :class:`Denotations` and its shortcuts must equal (its tests and
    ``benchmarks/features_denotations.py``). With ``memo``, sub-expressions are remembered there.
    """
    if memo is not None and node in memo:
        return memo[node]
    value = _defined(node, prims, objects, constants, memo)
    if memo is not None:
        memo[node] = value
    return value


def _defined(node: Node, prims: dict[str, np.ndarray], objects: int, constants: tuple[str, ...],
             memo: dict[Node, np.ndarray] | None) -> np.ndarray:
    pairs = next(iter(prims.values())).shape[0]
    op, a = node.op, node.args
    if op == "top":
        return np.ones((pairs, objects), bool)
    if op in ("pred", "role"):
        return prims[a[0]]
    if op == "proj":
        return prims[a[0]].any(axis=2 - a[1])
    if op == "nom":
        out = np.zeros((pairs, objects), bool)
        out[:, objects - len(constants) + constants.index(a[0])] = True
        return out
    return apply(op, [by_definition(x, prims, objects, constants, memo) for x in a])


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
    if op == "self":  # R(x, x)
        return np.diagonal(args[0], axis1=1, axis2=2).copy()
    if op == "comp":  # some y with R(x, y) and S(y, z)
        return _product(args[0], args[1])
    if op == "or":
        return args[0] | args[1]
    if op == "restrict":  # R(x, y) with y in C
        return args[0] & args[1][:, None, :]
    raise GrammarError(f"unknown constructor {op!r}")


def _product(r: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The boolean product of two batches of relations (float32 counts: exact below 2^24 objects)."""
    return np.matmul(r.astype(np.float32), s.astype(np.float32)) > 0


def closure(r: np.ndarray, succ: np.ndarray | None = None, pred_: np.ndarray | None = None) -> np.ndarray:
    """The transitive closure of a batch of relations (B, N, N); ``succ`` / ``pred_``: its links if known."""
    succ = _index(r, 2) if succ is None else succ
    if succ is not None:
        return _functional_closure(r, succ)
    pred_ = _index(r, 1) if pred_ is None else pred_
    if pred_ is not None:
        return _functional_closure(r.transpose(0, 2, 1), pred_).transpose(0, 2, 1)
    out = r.copy()
    while True:
        step = out | _product(out, out)
        if (step == out).all():
            return out
        out = step


def chain_any(c: np.ndarray, succ: np.ndarray, reflexive: bool) -> np.ndarray:
    """∃R⁺.C (``reflexive``: ∃R*.C) of a role with at most one successor per object (``succ``, (B, N), -1: none).

    C over x's successors (and x itself for R*), by doubling: after k steps ``acc[x]`` is C over
    x and its next 2^k - 1 successors, so log2 N steps cover every chain (a cycle too).
    """
    b, n = succ.shape
    m = n + 1  # object n of each row: past the end of a chain, in no concept
    acc = np.zeros((b, m), bool)
    acc[:, :n] = c
    link = np.full((b, m), n, np.int64)
    link[:, :n] = np.where(succ >= 0, succ, n)
    link += (np.arange(b) * m)[:, None]  # flat indexes: one gather per step
    first = link[:, :n].copy()
    acc, link = acc.ravel(), link.ravel()
    for _ in range(max(1, n.bit_length())):
        acc = acc | acc[link]
        link = link[link]
    return acc.reshape(b, m)[:, :n] if reflexive else acc[first]


def _functional_closure(r: np.ndarray, succ: np.ndarray) -> np.ndarray:
    """Closure of relations with at most one successor per object (``succ``, -1 for none): follow the links."""
    b, n, _ = r.shape
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


__all__ = ["Denotations", "apply", "by_definition", "chain_any", "closure"]
