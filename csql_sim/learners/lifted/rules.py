"""The lifted classifiers LQ-CS learns, and its two sweeps over them: specialization and generalization.

A rule's condition is a set of **literals**: (position, value) pairs over a move's feature
vector (the nine given atoms, or the generated literals of
:mod:`~csql_sim.learners.lifted.features`); a position it leaves out is ``#``. Each rule keeps,
for every position, the sum and count of the advantages it learned while that position was
0 and while it was 1: the statistics its specialization reads.

* :func:`specialize`: a rule whose advantages differ by more than ``tau`` between the two
  values of one of its free positions (both with ``min_experience`` updates) is split on the
  position that separates them most (the first of equal gaps), or on a position whose rarer
  value has only ``rare_experience`` updates but a gap above ``rare_gap`` (a rare split);
* :func:`generalize_once`: two rules of one kind whose conditions differ in one position
  only, as 0 and 1, both with ``min_experience`` updates and advantages within ``tau / 2``,
  are merged into one that leaves the position free.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

WIDE = 64
"""Feature vectors wider than this add their split statistics by matrix products."""
Literals = tuple[tuple[int, int], ...]
"""A condition: (position, value) pairs, by position."""


@dataclass(eq=False)
class Rule:
    """A lifted classifier being learned: condition, kind, advantage, error, experience and split statistics."""

    literals: Literals
    kind: str
    width: int
    advantage: float = 0.0
    error: float = 0.0
    experience: int = 0
    stats: np.ndarray | None = field(default=None, repr=False)

    @property
    def specificity(self) -> int:
        """The number of positions the condition fixes."""
        return len(self.literals)

    def matches(self, bits: np.ndarray, kind: str) -> bool:
        """Whether the rule's kind is ``kind`` and every literal holds in ``bits``."""
        return kind == self.kind and all(bits[i] == v for i, v in self.literals)

    def update(self, advantage: float, beta: float) -> None:
        """One update of the advantage and its error (MAM: plain averages for the first 1/beta updates)."""
        self.experience += 1
        rate = max(beta, 1.0 / self.experience)
        self.error += rate * (abs(advantage - self.advantage) - self.error)
        self.advantage += rate * (advantage - self.advantage)

    def add_stats(self, advantages: np.ndarray, rows: np.ndarray) -> None:
        """Add the advantages of some updates, with their feature rows (updates, width), to the split statistics.

        Narrow rows (the given atoms) are added one by one, in order; wide ones (generated
        features) as one matrix product per call.
        """
        if self.stats is None:
            self.stats = np.zeros((4, self.width))
        s = self.stats
        if self.width > WIDE:
            ones = rows.astype(np.float64)
            adv = np.asarray(advantages, np.float64)
            s[2] += adv @ ones
            s[3] += ones.sum(axis=0)
            s[0] += adv.sum() - adv @ ones
            s[1] += len(adv) - ones.sum(axis=0)
            return
        for a, row in zip(advantages, rows, strict=True):
            one = row.astype(np.float64)
            zero = 1.0 - one
            s[0] += a * zero
            s[1] += zero
            s[2] += a * one
            s[3] += one


def split_position(rule: Rule, tau: float, min_experience: int, rare_experience: int | None = None,
                   rare_gap: float = math.inf) -> int | None:
    """The free position to split on, or None: the one whose two values' mean advantages differ most.

    Both values need ``min_experience`` updates and the gap must exceed tau; of equal gaps the
    first (with generated features, ordered simplest first, the simplest). The largest gap, not
    the split that explains the most of the advantages' spread: a feature that isolates a
    decisive situation (a block already in place, a move that uncovers a needed block) beats
    one that halves the moves by an accident of five-block worlds (``docs/features.md``).

    A **rare split**: a position whose rarer value has fewer than ``min_experience`` updates but
    at least ``rare_experience`` may split too, when its gap exceeds ``rare_gap`` (moves, far
    above tau): a situation the training meets seldom, such as a well-placed block taken off
    onto another block, that costs a move or more.
    """
    if rule.stats is None or rule.experience < min_experience:
        return None
    s0, c0, s1, c1 = rule.stats
    low = np.minimum(c0, c1)
    valid = low >= (min_experience if rare_experience is None else min(rare_experience, min_experience))
    for i, _ in rule.literals:
        valid[i] = False
    if not valid.any():
        return None
    gap = np.full(rule.width, -np.inf)
    gap[valid] = np.abs(s0[valid] / c0[valid] - s1[valid] / c1[valid])
    gap[gap <= np.where(low >= min_experience, tau, rare_gap)] = -np.inf
    best = int(np.argmax(gap))
    return best if np.isfinite(gap[best]) else None


def specialize(rules: list[Rule], tau: float, min_experience: int, rare_experience: int | None = None,
               rare_gap: float = math.inf) -> tuple[list[Rule], int]:
    """Split every rule that hides a difference (:func:`split_position`); the new list and the number of splits."""
    out, splits = [], 0
    for r in rules:
        best = split_position(r, tau, min_experience, rare_experience, rare_gap)
        if best is None:
            out.append(r)
            continue
        s0, c0, s1, c1 = (float(x[best]) for x in r.stats)
        for value, total, count in ((0, s0, c0), (1, s1, c1)):
            literals = tuple(sorted((*r.literals, (best, value))))
            out.append(Rule(literals, r.kind, r.width, total / count, r.error, int(count)))
        splits += 1
    return out, splits


def generalize_once(rules: list[Rule], tau: float, min_experience: int) -> list[Rule] | None:
    """The list with the first mergeable pair merged, or None if no pair is."""
    for i, a in enumerate(rules):
        for b in rules[i + 1:]:
            pos = sibling_position(a, b)
            if pos is None or min(a.experience, b.experience) < min_experience \
                    or abs(a.advantage - b.advantage) >= tau / 2:
                continue
            total = a.experience + b.experience
            merged = Rule(tuple(x for x in a.literals if x[0] != pos), a.kind, a.width,
                          (a.advantage * a.experience + b.advantage * b.experience) / total,
                          max(a.error, b.error), total)
            return [r for r in rules if r is not a and r is not b] + [merged]
    return None


def sibling_position(a: Rule, b: Rule) -> int | None:
    """The one position where a and b differ as 0 and 1 (same kind, same elsewhere), else None."""
    if a.kind != b.kind or len(a.literals) != len(b.literals):
        return None
    diff = [x for x, y in zip(a.literals, b.literals, strict=True) if x != y]
    if len(diff) != 1:
        return None
    pos = diff[0][0]
    return pos if dict(b.literals).get(pos) == 1 - diff[0][1] else None


__all__ = ["Literals", "Rule", "generalize_once", "sibling_position", "specialize", "split_position"]
