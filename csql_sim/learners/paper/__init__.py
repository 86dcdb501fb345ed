"""The paper's tabular learners (section 6) behind one contract.

The contract is :class:`~csql_sim.learners.paper.learner.Learner` (:mod:`.learner`): a learner
trains from one ``numpy.random.Generator``, reports its learning curve and writes its rule base.
``lt-ql`` (:mod:`.lt_ql`), ``cs-ql`` (:mod:`.cs_ql`), ``cs-bb-bz`` and ``cs-bb-rw``
(:mod:`.bucket_brigade`) run trial by trial (:mod:`.trial`), choose actions by :mod:`.selection`
and may replay experience (:mod:`.replay`); their parameters and ranges are :mod:`.params` and
:mod:`.params_bounds`; :mod:`.coverage` reads which classifiers a rule base uses.

Contract: the bottom of ``learners``. It imports only ``core`` and ``infra``; every other
family may import it. Outside ``learners``, import these names from this package.
"""

from csql_sim.learners.paper.coverage import coverage_rows, coverage_table
from csql_sim.learners.paper.learner import Curve, Learner, Transition, UniformStream
from csql_sim.learners.paper.params import (
    CommonParams,
    CSQLParams,
    default_params,
    default_trials,
    defaults_for_blocks,
    resolve_params,
    with_overrides,
)
from csql_sim.learners.paper.selection import boltzmann
from csql_sim.learners.paper.trial import TEST_EVERY, StepLearner

__all__ = [
    "CSQLParams", "CommonParams", "Curve", "Learner", "StepLearner", "TEST_EVERY", "Transition",
    "UniformStream", "boltzmann", "coverage_rows", "coverage_table", "default_params", "default_trials",
    "defaults_for_blocks", "resolve_params", "with_overrides",
]
