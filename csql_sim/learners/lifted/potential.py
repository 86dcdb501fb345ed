"""A tie-break over generated features: the count that best predicts the moves left, fitted to the reward.

Plans of one length are equally good at five blocks, but not all of their first moves carry to
large worlds: among them, those that leave fewer moves for later are the ones to learn. A
:class:`Potential` states "fewer moves left" over the generated features alone:

1. :func:`state_values` runs value iteration of the task's reward (-1 per move, 0 at the goal)
   on the enumerated hand-empty states of a training world, for each training goal: the
   exact moves left, from the reward and the world model alone;
2. :func:`fit_potential` takes, among the generated concepts, the one whose count ``|C|`` is
   most correlated with those values on the learner's sampled (state, goal) pairs (ties: the
   simplest, found first), and fits ``h = slope * |C| + intercept`` by least squares.

The learner's step cost is then 1 plus ``early`` times h of the state after the move
(:class:`~csql_sim.learners.lifted.ground.RewardCosts`): too small to trade a move for, it
prefers, among plans of one length, the one that makes h fall sooner. Which concept is chosen
is data, not a name: nothing here knows what the concept means.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csql_sim.core.features.denotation import Denotations
from csql_sim.core.features.grammar import Node
from csql_sim.core.state.moves import after, moves
from csql_sim.core.state.world import State


@dataclass(frozen=True)
class Potential:
    """``h = slope * |concept| + intercept``, the fitted estimate of the moves left.

    Attributes:
        concept: the concept's written form (:meth:`Node.text`).
        slope, intercept: the least-squares fit of the values on the sample.
        correlation: the count's correlation with the values there.
        samples: (state, goal) pairs fitted on.
    """

    concept: str
    slope: float
    intercept: float
    correlation: float
    samples: int

    def of(self, count: float | np.ndarray) -> float | np.ndarray:
        """The estimate ``h`` of a count (or of an array of counts)."""
        return self.slope * count + self.intercept

    def as_dict(self) -> dict:
        """The fit as plain values."""
        return {"concept": self.concept, "slope": round(self.slope, 4), "intercept": round(self.intercept, 4),
                "correlation": round(self.correlation, 4), "samples": self.samples}


def state_values(states: list[State], goals: list[State]) -> dict[tuple[State, State], float]:
    """The moves left from every hand-empty state of ``states`` to every hand-empty goal, by value iteration.

    ``states`` must be closed under moves (every state of one world). Unreachable pairs are left out.
    """
    hand_empty = [s for s in states if s.held is None]
    index = {s: i for i, s in enumerate(hand_empty)}
    succ = [[index[after(s, m)] for m in moves(s)] for s in hand_empty]
    width = max((len(row) for row in succ), default=0)
    table = np.full((len(hand_empty), max(width, 1)), len(hand_empty), np.int64)
    for i, row in enumerate(succ):
        table[i, :len(row)] = row
    targets = [g for g in dict.fromkeys(goals) if g.held is None and g in index]
    values = np.full((len(targets), len(hand_empty) + 1), np.inf)
    values[np.arange(len(targets)), [index[g] for g in targets]] = 0.0
    while True:
        backed = np.minimum(values[:, :-1], values[:, table].min(axis=2) + 1.0)
        if np.array_equal(backed, values[:, :-1]):
            break
        values[:, :-1] = backed
    return {(s, g): float(values[k, i]) for k, g in enumerate(targets) for s, i in index.items()
            if np.isfinite(values[k, i])}


def fit_potential(concepts: tuple[Node, ...], den: Denotations, rows: np.ndarray, values: np.ndarray
                  ) -> Potential | None:
    """The concept whose count best predicts ``values`` at batch ``rows`` of ``den`` (module docstring).

    None when no concept's count varies on the sample.
    """
    if len(rows) < 2 or np.ptp(values) == 0:
        return None
    y = values - values.mean()
    best: tuple[float, Node, np.ndarray] | None = None
    for node in concepts:
        x = den.count(node)[rows].astype(float)
        x = x - x.mean()
        norm = float(np.sqrt((x * x).sum() * (y * y).sum()))
        if norm == 0:
            continue
        r = float((x * y).sum()) / norm
        if best is None or abs(r) > abs(best[0]) + 1e-12:
            best = (r, node, den.count(node)[rows].astype(float))
    if best is None:
        return None
    r, node, x = best
    slope, intercept = np.polyfit(x, values, 1)
    return Potential(node.text(), float(slope), float(intercept), r, len(rows))


__all__ = ["Potential", "fit_potential", "state_values"]
