"""Generated features as LQ-CS's vocabulary, learned from the task's reward alone.

:class:`GeneratedFeatures` reads the literals of concepts generated from a PDDL domain's
predicates (:mod:`~csql_sim.learners.lifted.features`), evaluated towards the goal as it is
(a goal that holds a block included); its ground values come from the reward alone, -1 per
action and 0 at the goal (:class:`~csql_sim.learners.lifted.ground.RewardCosts`); after a pick
the learner puts the move's own block where the move says, as the policy does
(:class:`~csql_sim.core.policies.feature_policy.FeaturePolicy`). No hand-written concept of
the task is imported here or below (the import contract in ``pyproject.toml``).

:func:`train_generated` is LQ-CS over these features.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Hashable

import numpy as np

from csql_sim.core.features.formulation import BUILTIN, MAX_DOMAIN_BYTES, Formulation, load_formulation
from csql_sim.core.features.generate import BASE, EXTENDED
from csql_sim.core.features.move_features import Literal
from csql_sim.core.policies.lifted_classifier import LiftedQClassifier
from csql_sim.core.state.moves import Move
from csql_sim.core.state.world import State
from csql_sim.infra.assets import asset_text
from csql_sim.infra.files import read_text_file
from csql_sim.learners.lifted.features import FeatureSpace, FeatureTable, build_space
from csql_sim.learners.lifted.ground import PotentialCosts
from csql_sim.learners.lifted.learner import LiftedRun, learn
from csql_sim.learners.lifted.params import LiftedParams
from csql_sim.learners.lifted.rules import Literals
from csql_sim.learners.lifted.vocab import Vocabulary
from csql_sim.learners.paper.params import ParamsError


class GeneratedFeatures(Vocabulary):
    """Literals of concepts generated from a formulation's predicates, within complexity ``complexity``."""

    name = "generated"
    cache_relations = False
    warmup = 3
    fresh_stats = True
    commits = True
    replay_passes = 16
    """Values start at 0, not at a lower bound: a sweep runs value iteration until it settles (five-block
    worlds are at most a dozen moves deep), so the advantages learned next read exact values."""

    def __init__(self, form: Formulation, domain: str, complexity: int, sample: int,
                 constructors: tuple[str, ...] = BASE, early: float = 0.0) -> None:
        self.form, self.domain, self.complexity, self.sample = form, domain, complexity, sample
        self.constructors = constructors
        self.hand = form.hand
        self.costs = PotentialCosts(2 if form.hand else 1, early)
        self.space: FeatureSpace | None = None
        self.tables: dict[int, FeatureTable] = {}

    def prepare(self, n: int, goals: list[State], rng: np.random.Generator) -> None:
        """Build the feature space on the first world met; table every world's pairs."""
        if not self.form.hand:
            goals = [g for g in goals if g.held is None] or goals
        if self.space is None:
            self.space = build_space(self.form, n, goals, rng, self.complexity, self.sample,
                                     self.constructors, fit=self.costs.early > 0)
            self.width = len(self.space.literals)
            if self.space.potential is not None:
                self.costs.estimate = self.estimate
        self.tables[n] = FeatureTable(self.space, n, goals)

    def estimate(self, state: State, target: State) -> float:
        """The fitted potential of (state, target) (:mod:`~csql_sim.learners.lifted.potential`)."""
        return self.tables[state.n].estimate(state, target)

    @property
    def literals(self) -> tuple[Literal, ...]:
        """The literals of the feature space (empty before :meth:`prepare`)."""
        return () if self.space is None else self.space.literals

    def relations(self, state: State, target: State) -> tuple[tuple[Move, ...], np.ndarray]:
        return self.tables[state.n].relations(state, target)

    def cover(self, bits: np.ndarray) -> Literals:
        return ()

    def match_key(self, i: int, j: int, bits: np.ndarray, kind: str) -> Hashable:
        return i, j

    def summary(self) -> tuple[tuple[Literal, ...], str, dict]:
        space = self.space
        if space is None:
            return (), "", {}
        figures = {"formulation": self.form.name, "complexity": space.complexity, "candidates": space.candidates,
                   "concepts": space.generated, "literals": len(space.literals)}
        if space.potential is not None:
            figures["potential"] = space.potential.as_dict()
        return space.literals, self.domain, figures


def generated_vocabulary(params: LiftedParams) -> GeneratedFeatures:
    """The generated features the parameters name (``domain``, ``complexity``, ``grammar``, ``sample``)."""
    form = load_formulation(params.domain)
    domain = asset_text("domains", BUILTIN[params.domain]) if params.domain in BUILTIN else \
        read_text_file(params.domain, MAX_DOMAIN_BYTES, "PDDL domain")
    constructors = EXTENDED if params.grammar == "extended" else BASE
    return GeneratedFeatures(form, domain, params.complexity, params.sample, constructors, params.early)


def train_generated(params: LiftedParams, rng: np.random.Generator,
                    progress: Callable[[int, int], None] | None = None,
                    checkpoints: Collection[int] = (),
                    at_checkpoint: Callable[[int, tuple[LiftedQClassifier, ...]], None] | None = None) -> LiftedRun:
    """LQ-CS over generated features (:func:`~csql_sim.learners.lifted.learner.learn`); ``features`` must say so."""
    if params.features != "generated":
        raise ParamsError("this learner reads generated features (features='generated')")
    return learn(params, generated_vocabulary(params), rng, progress, checkpoints, at_checkpoint)


__all__ = ["GeneratedFeatures", "generated_vocabulary", "train_generated"]
