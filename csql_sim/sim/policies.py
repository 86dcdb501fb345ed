"""Where the physical executor gets its policy: the BFS planner or a rule base file."""

from __future__ import annotations

import os

from csql_sim.errors import CsqlError
from csql_sim.planner import BfsPolicy
from csql_sim.policy import Policy


def load_policy(path: str | os.PathLike | None, n: int | None = None) -> tuple[Policy, int | None]:
    """The greedy policy of a rule base from ``csql-sim train``, or BFS when ``path`` is None.

    Args:
        path: a rule-base file, or None for the BFS planner.
        n: the number of blocks the caller expects (checked against the rule base).

    Returns:
        The policy and the rule base's number of blocks (``n`` for BFS).

    Raises:
        CsqlError: if the file cannot be read or is for another number of blocks.
    """
    if path is None:
        return BfsPolicy(), n
    try:
        from csql_sim.classifiers import ClassifierList
        from csql_sim.policy import QPolicy
        from csql_sim.rulebase import load
    except ImportError:  # pragma: no cover - depends on the rule-base modules
        raise CsqlError("rule bases are not supported yet") from None
    rulebase = load(path)
    if n is not None and rulebase.blocks != n:
        raise CsqlError(f"rule base {os.fspath(path)!r} is for {rulebase.blocks} blocks, not {n}")
    return QPolicy(ClassifierList(rulebase.classifiers), rulebase.blocks), rulebase.blocks
