"""Lifted learning: LQ-CS, lifted Q-classifiers over given atoms or generated features.

:mod:`.ql` is the learner (:func:`~csql_sim.learners.lifted.ql.train_lifted`); its vocabulary
(:mod:`.vocab`) is either the given atoms or the features generated and pruned on small
worlds (:mod:`.features`); :mod:`.rules` generalizes and specializes conditions, :mod:`.ground`
holds the exact values it learns from, and :mod:`.committee` learns K populations from one seed.

Contract: lifted learning never imports the tabular engines (:mod:`csql_sim.learners.engines`);
it imports :mod:`csql_sim.learners.paper` (only the parameters' error), ``core`` and ``infra``.
Outside ``learners``, import these names from this package.
"""

from csql_sim.learners.lifted.committee import train_committee
from csql_sim.learners.lifted.ql import LiftedParams, LiftedRun, train_lifted

__all__ = ["LiftedParams", "LiftedRun", "train_committee", "train_lifted"]
