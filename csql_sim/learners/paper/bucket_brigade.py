"""CS-BB-BZ and CS-BB-RW: the classifier system with Holland's bucket brigade (section 6).

The classifier system (processing block, world model) is CS-QL's; only credit assignment
and selection differ. No discounting. Constants (:class:`BucketBrigadeParams`, where their
choice is explained): the active classifier bids ``bid * S`` and pays it to the
classifier active one step before it in the trial; at the goal it receives
``bid * payoff``; matched candidates that are not selected pay a tax ``tax * S``.

The learned value is the strength; the exported rule base keeps each classifier's
``q`` untouched, and its ``meta["value"]`` says that greedy plans follow ``strength``.
"""

from __future__ import annotations

import numpy as np

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import RClassifier
from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.model.processing_block import MatchSet
from csql_sim.learners.paper.cs_ql import ClassifierSystemLearner
from csql_sim.learners.paper.params import BucketBrigadeParams
from csql_sim.learners.paper.selection import boltzmann, roulette


class BucketBrigade(ClassifierSystemLearner):
    """CS-BB-BZ: bucket brigade, Boltzmann selection (eq. 3) over strengths."""

    method = "cs-bb-bz"
    params: BucketBrigadeParams

    def __init__(self, n: int, params: BucketBrigadeParams, rng: np.random.Generator,
                 rules: tuple[RClassifier, ...] | None = None) -> None:
        super().__init__(n, params, rng, rules)
        self._previous: QClassifier | None = None

    def new_fields(self) -> dict:
        """A new classifier starts at strength ``s0``."""
        return {"q": 0.0, "strength": self.params.s0, "error": 0.0, "last_active": self.t, "born": self.t}

    def begin_episode(self) -> None:
        """An episode starts with no predecessor to pay."""
        self._previous = None

    def candidate_value(self, c: QClassifier) -> float:
        """The strength."""
        return c.strength

    def select(self, match_set: MatchSet, temperature: float, u: float) -> int:
        """Boltzmann over the candidates' strengths."""
        return boltzmann([c.strength for c in match_set.candidates], temperature, u)

    def update(self, match_set: MatchSet, i: int, nxt: MatchSet | None, t: int) -> None:
        """The bucket brigade: pay the bid to the predecessor; collect payoff at the goal."""
        p = self.params
        c = match_set.candidates[i]
        bid = p.bid * c.strength
        c.strength -= bid
        if self._previous is not None:
            self._previous.strength += bid
        if nxt is None:
            c.strength += p.bid * p.payoff
        if p.tax:
            for j, other in enumerate(match_set.candidates):
                if j != i:
                    other.strength -= p.tax * other.strength
        c.last_active = t
        self._previous = c

    def rulebase(self, meta: dict | None = None) -> RuleBase:
        """The classifier list; ``meta["value"] = "strength"`` tells planners what to follow."""
        return super().rulebase({**(meta or {}), "value": "strength"})


class BucketBrigadeRoulette(BucketBrigade):
    """CS-BB-RW: bucket brigade, roulette-wheel selection (P proportional to strength)."""

    method = "cs-bb-rw"

    def select(self, match_set: MatchSet, temperature: float, u: float) -> int:
        """The roulette wheel over the candidates' strengths (T is unused)."""
        return roulette([c.strength for c in match_set.candidates], u)
