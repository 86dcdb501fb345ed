"""Generalization and pruning: from a learned table to fewer, more general classifiers.

:mod:`.compaction` compresses a goal-form table into ``#`` rules (the ``generalize``
command), :mod:`.xcs_ql` generalizes while it learns (CS-QL's critic with an XCS-style
population), :mod:`.pruning` drops classifiers under a threshold and prints Figure 6's table.

Contract: imports :mod:`csql_sim.learners.paper`, ``core`` and ``infra``; never the
engines or the lifted learners. Outside ``learners``, import these names from this package.
"""

from csql_sim.learners.generalize.compaction import generalize
from csql_sim.learners.generalize.pruning import count_q, figure6_rows, figure6_table, prune

__all__ = ["count_q", "figure6_rows", "figure6_table", "generalize", "prune"]
