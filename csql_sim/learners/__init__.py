"""The paper's four learners (section 6) behind one contract (:mod:`~csql_sim.learners.learner`).

``lt-ql`` (:mod:`~csql_sim.learners.lt_ql`), ``cs-ql`` (:mod:`~csql_sim.learners.cs_ql`, with
an array engine in :mod:`~csql_sim.learners.fast_engine`), ``cs-bb-bz`` and ``cs-bb-rw``
(:mod:`~csql_sim.learners.bucket_brigade`); :mod:`~csql_sim.learners.training` makes and
trains them.
"""
