"""LQ-CS over either vocabulary: :func:`train_lifted`, the entry point of ``train-lifted``.

The learner itself is :mod:`csql_sim.learners.lifted.learner`; this module picks its
vocabulary from the parameters: the given atoms (:class:`~csql_sim.learners.lifted.given.GivenAtoms`)
or features generated from the domain's predicates
(:func:`~csql_sim.learners.lifted.generated.train_generated`). A run over the given atoms plans
with :class:`~csql_sim.core.policies.lifted_policy.LiftedPolicy` (:class:`GivenRun`).
"""

from __future__ import annotations

from collections.abc import Callable, Collection
from dataclasses import dataclass, fields

import numpy as np

from csql_sim.core.policies.lifted_classifier import LiftedQClassifier
from csql_sim.core.policies.lifted_policy import LiftedPolicy
from csql_sim.learners.lifted.generated import train_generated
from csql_sim.learners.lifted.given import GivenAtoms
from csql_sim.learners.lifted.learner import LiftedRun, learn
from csql_sim.learners.lifted.params import LiftedParams


@dataclass(frozen=True)
class GivenRun(LiftedRun):
    """A run over the given atoms: its policy is :class:`LiftedPolicy`."""

    def policy(self, meta: dict | None = None) -> LiftedPolicy:
        """The greedy policy of the learned classifiers over the given atoms."""
        return LiftedPolicy(self.classifiers, meta)


def train_lifted(params: LiftedParams, rng: np.random.Generator,
                 progress: Callable[[int, int], None] | None = None,
                 checkpoints: Collection[int] = (),
                 at_checkpoint: Callable[[int, tuple[LiftedQClassifier, ...]], None] | None = None) -> LiftedRun:
    """Learn lifted Q-classifiers from an empty population over the vocabulary ``params.features`` names.

    Args:
        params: the learner's parameters.
        rng: the run's one generator (pairs, exploration).
        progress: called with (trials done, trials) after every sweep.
        checkpoints: trial counts at which to call ``at_checkpoint``.
        at_checkpoint: called with (trials done, the classifiers then), after that trial's sweep
            if it has one; the run goes on unchanged, so a checkpoint at a multiple of ``sweep``
            gives the classifiers of a run of that many trials.
    """
    if params.features == "generated":
        return train_generated(params, rng, progress, checkpoints, at_checkpoint)
    run = learn(params, GivenAtoms(params.atoms, params.early), rng, progress, checkpoints, at_checkpoint)
    return GivenRun(**{f.name: getattr(run, f.name) for f in fields(run)})


__all__ = ["GivenRun", "train_lifted"]
