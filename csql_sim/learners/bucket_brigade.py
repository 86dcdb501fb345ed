"""CS-BB-BZ and CS-BB-RW: the classifier system with Holland's bucket brigade (section 6).

The classifier system (match, cover, world model) is CS-QL's; only credit assignment and
selection differ. No discounting. Constants (:class:`BucketBrigadeParams`): the active
classifier bids ``bid * S`` (bid = 0.2) and pays it to the classifier active one step
before it in the trial; at the goal it receives ``bid * payoff``; matched candidates
that are not selected pay a tax ``tax * S`` (tax = 0 by default: Holland's bid tax is
off, so only the brigade moves strength).
"""

from __future__ import annotations

import numpy as np

from csql_sim.classifiers import Classifier, Q
from csql_sim.learners.csql import ClassifierSystemLearner, Node
from csql_sim.learners.params import BucketBrigadeParams
from csql_sim.learners.selection import boltzmann, roulette


class BucketBrigade(ClassifierSystemLearner):
    """CS-BB-BZ: bucket brigade, Boltzmann selection (eq. 3) over strengths."""

    method = "cs-bb-bz"
    params: BucketBrigadeParams

    def __init__(self, n: int, params: BucketBrigadeParams, rng: np.random.Generator) -> None:
        super().__init__(n, params, rng)
        self._previous: Classifier | None = None

    def new_fields(self) -> dict:
        """A new classifier starts at strength ``s0``."""
        return {"q": 0.0, "strength": self.params.s0, "error": 0.0, "last_active": self.t}

    def begin_trial(self) -> None:
        """A trial starts with no predecessor to pay."""
        self._previous = None

    def value(self, node: Node, i: int) -> float:
        """The strength of candidate ``i``."""
        return node.qs[i].strength

    def select(self, node: Node, temperature: float, u: float) -> int:
        """Boltzmann over the candidates' strengths."""
        return boltzmann([c.strength for c in node.qs], temperature, u)

    def update(self, node: Node, i: int, nxt: Node | None, t: int) -> None:
        """The bucket brigade: pay the bid to the predecessor; collect payoff at the goal."""
        p = self.params
        c = node.qs[i]
        bid = p.bid * c.strength
        c.strength -= bid
        if self._previous is not None:
            self._previous.strength += bid
        if nxt is None:
            c.strength += p.bid * p.payoff
        if p.tax:
            for j, other in enumerate(node.qs):
                if j != i:
                    other.strength -= p.tax * other.strength
        c.last_active = t
        self._previous = c

    def settle(self) -> None:
        """Ages, and ``q`` := strength so greedy planning over the file uses strengths."""
        super().settle()
        for c in self.classifiers:
            if c.kind == Q:
                c.q = c.strength


class BucketBrigadeRoulette(BucketBrigade):
    """CS-BB-RW: bucket brigade, roulette-wheel selection (P proportional to strength)."""

    method = "cs-bb-rw"

    def select(self, node: Node, temperature: float, u: float) -> int:
        """The roulette wheel over the candidates' strengths (T is unused)."""
        return roulette([c.strength for c in node.qs], u)
