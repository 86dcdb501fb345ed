"""The paper's four learners (section 6) behind one contract (:mod:`~csql_sim.learners.paper.learner`).

``lt-ql`` (:mod:`~csql_sim.learners.paper.lt_ql`), ``cs-ql`` (:mod:`~csql_sim.learners.paper.cs_ql`, with
an array engine in :mod:`~csql_sim.learners.engines.fast_engine`), ``cs-bb-bz`` and ``cs-bb-rw``
(:mod:`~csql_sim.learners.paper.bucket_brigade`); :mod:`~csql_sim.learners.training.tabular` makes and
trains them.
"""
