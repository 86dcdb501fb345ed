"""The compiled engines: the paper's ``cs-ql`` and ``lt-ql`` on arrays, compiled with numba.

:class:`~csql_sim.learners.engines.fast_engine.FastCSQL` and
:class:`~csql_sim.learners.engines.lt_fast.FastTabularQ` follow the reference learners'
trajectories exactly (byte-identical rule files) and keep the
:class:`~csql_sim.learners.paper.learner.Learner` contract; the kernels (:mod:`.fast_kernels`,
:mod:`.lt_kernels`) are imported on first use (importing numba costs most of a second) and are
called with the signal handlers held back (:mod:`.kernel_calls`).

Contract: the engines import only :mod:`csql_sim.learners.paper` (the contract and the
parameters), ``core`` and ``infra``; nothing above them. Only
:mod:`csql_sim.learners.training` chooses an engine, so this package re-exports nothing.
"""

