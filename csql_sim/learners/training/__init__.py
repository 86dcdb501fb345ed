"""Training a table: choosing the learner and engine, in one process or sharded by goal.

:mod:`.tabular` makes and trains every tabular learner (:func:`~csql_sim.learners.training.tabular.make_learner`
is the one place an engine is chosen); :mod:`.shards` trains six blocks sharded by goal, in
parallel, resumably; :mod:`.costs` says what a run costs in memory, disk and time before it starts.

Contract: the top of ``learners``: it may import every tabular family (paper, engines,
generalize) and no family imports it. Outside ``learners``, import these names from this package.
"""

from csql_sim.learners.training.costs import (
    PROCESS_BYTES,
    available_memory,
    check_fits,
    estimate,
    format_size,
    parse_size,
)
from csql_sim.learners.training.shards import ShardRun, default_shards, read_reports, train_sharded
from csql_sim.learners.training.tabular import METHODS, PAPER_METHODS, make_learner, train, train_learner

__all__ = [
    "METHODS", "PAPER_METHODS", "PROCESS_BYTES", "ShardRun", "available_memory", "check_fits",
    "default_shards", "estimate", "format_size", "make_learner", "parse_size", "read_reports", "train",
    "train_learner", "train_sharded",
]
