"""The learners, one subpackage per family, each stating its contract in its ``__init__``.

* :mod:`~csql_sim.learners.paper`: the paper's four tabular learners (section 6) behind one
  contract (:class:`~csql_sim.learners.paper.learner.Learner`);
* :mod:`~csql_sim.learners.engines`: their compiled array engines;
* :mod:`~csql_sim.learners.generalize`: compressing a learned table into ``#`` rules, and pruning;
* :mod:`~csql_sim.learners.lifted`: LQ-CS, lifted Q-classifiers for plans at any n;
* :mod:`~csql_sim.learners.training`: making and training a tabular learner, sharded by goal
  at six blocks, and what a run costs.

Families import downwards only (training > generalize | engines | lifted > paper); outside
``learners``, a family is imported through its ``__init__``.
"""
