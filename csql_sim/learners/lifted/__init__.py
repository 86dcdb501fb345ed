"""Lifted learning: LQ-CS, lifted Q-classifiers over given atoms or generated features.

:mod:`.learner` is the learner, :mod:`.params` its parameters; its vocabulary (:mod:`.vocab`)
is either the given atoms (:mod:`.given`) or the features generated and pruned on small worlds
(:mod:`.generated`, :mod:`.features`); :mod:`.ql` picks one (:func:`~csql_sim.learners.lifted.ql.train_lifted`);
:mod:`.rules` generalizes and specializes conditions, :mod:`.ground` holds the exact values it
learns from, and :mod:`.committee` learns K populations from one seed over generated features.

Contract: lifted learning never imports the tabular engines (:mod:`csql_sim.learners.engines`);
it imports :mod:`csql_sim.learners.paper` (only the parameters' error), ``core`` and ``infra``.
Outside ``learners``, import these names from this package.
"""

from csql_sim.learners.lifted.committee import train_committee
from csql_sim.learners.lifted.learner import LiftedRun
from csql_sim.learners.lifted.params import LiftedParams
from csql_sim.learners.lifted.ql import train_lifted

__all__ = ["LiftedParams", "LiftedRun", "train_committee", "train_lifted"]
