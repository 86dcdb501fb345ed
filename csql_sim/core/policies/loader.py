"""Loading a policy: a rule file's kind picks its loader from one registry, :data:`LOADERS`.

:func:`load_policy` reads the file once (:func:`csql_sim.core.files.kinds.read_rule_file`,
which also tells its kind) and hands what it read to the loader of that kind:

* a ground rule base, YAML or npz: its greedy table (:class:`GreedyTable`);
* a goal-form rule base, YAML or npz: its default hierarchy (:class:`DefaultHierarchy`) as a
  greedy table;
* a sharded rule base's directory: read lazily, shard by shard (:class:`ShardedPolicy`);
* lifted Q-classifiers: a :class:`LiftedPolicy`, for any number of blocks (over generated
  features, a :class:`~csql_sim.core.policies.feature_policy.FeaturePolicy`; a committee of
  them, a :class:`~csql_sim.core.policies.committee_policy.CommitteePolicy`).

Without a file, the policy is BFS (:class:`~csql_sim.core.model.search.BfsPolicy`). Every
one of them implements the policy contract (:class:`csql_sim.core.policies.contract.Policy`).
"""

from __future__ import annotations

import os
from collections.abc import Callable

from csql_sim.core.classifiers.lifted_rule import read_versioned_json
from csql_sim.core.files import kinds
from csql_sim.core.files.kinds import RuleFile, read_rule_file
from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.files.rulebase_npz import arrays_from_bytes
from csql_sim.core.files.rulebase_npz import loads as npz_loads
from csql_sim.core.files.rulebase_yaml import RuleBaseError, loads
from csql_sim.core.model.search import BfsPolicy
from csql_sim.core.policies.committee_policy import COMMITTEE_VERSION, committee_from_doc
from csql_sim.core.policies.contract import Policy
from csql_sim.core.policies.default_hierarchy import DefaultHierarchy
from csql_sim.core.policies.feature_policy import feature_policy_from_doc
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.core.policies.lifted_classifier import LIFTED_Q_FORMAT, LIFTED_Q_VERSION, LiftedPolicyError
from csql_sim.core.policies.lifted_policy import loads_lifted_policy
from csql_sim.core.policies.sharded_policy import ShardedPolicy
from csql_sim.core.state.state_count import count_text, state_count
from csql_sim.core.state.world import MAX_BLOCKS
from csql_sim.infra.errors import CsqlError

Loader = Callable[[RuleFile, int | None, bool], Policy]
"""A kind's loader: ``(rule file as read, blocks expected or None, progress bar) -> policy``."""

LIFTED_HINT = "past six blocks plan with lifted rules (--rules FILE), which hold for any n, or with --planner gn1"


def _for_n(table: GreedyTable, found: RuleFile, n: int | None) -> GreedyTable:
    """``table`` if it is for ``n`` blocks (or any n is asked for); else a one-line error."""
    if n is not None and table.n != n:
        raise CsqlError(f"rule base {found.source!r} is for {table.n} blocks, not {n}")
    return table


def _ground_yaml(found: RuleFile, n: int | None, progress: bool) -> Policy:
    """QPolicy's answers as a table, from YAML (refused from the header if for another n)."""
    return _for_n(GreedyTable.from_rulebase(loads(found.text(), found.source, n, progress)), found, n)


def _ground_npz(found: RuleFile, n: int | None, progress: bool) -> Policy:
    """QPolicy's answers as a table, straight from the npz arrays."""
    return _for_n(GreedyTable.from_npz(*arrays_from_bytes(found.content(), found.source, RuleBaseError)), found, n)


def _hierarchy(rulebase: RuleBase) -> GreedyTable:
    """A goal-form rule base's default hierarchy, every pair decided at once, as a greedy table."""
    hierarchy = DefaultHierarchy.from_rulebase(rulebase)
    return GreedyTable(hierarchy.n, hierarchy.decisions().best)


def _goal_yaml(found: RuleFile, n: int | None, progress: bool) -> Policy:
    """The default hierarchy of goal-form Q-classifiers in YAML."""
    return _hierarchy(loads(found.text(), found.source, n, progress))


def _goal_npz(found: RuleFile, n: int | None, progress: bool) -> Policy:
    """The default hierarchy of goal-form Q-classifiers in npz."""
    rulebase = npz_loads(found.content(), found.source, RuleBaseError)
    if n is not None and rulebase.blocks != n:
        raise RuleBaseError(f"rule file {found.source!r} is for {rulebase.blocks} blocks, not {n}")
    return _hierarchy(rulebase)


def _sharded(found: RuleFile, n: int | None, progress: bool) -> Policy:
    """A sharded rule base, its manifest checked now and each shard read when a goal first needs it."""
    return ShardedPolicy.open(found.path, n)


def _lifted(found: RuleFile, n: int | None, progress: bool) -> Policy:
    """Lifted Q-classifiers, over the given atoms or over generated features: any number of blocks."""
    return loads_lifted_file(found.text(), f"lifted Q-classifier file {found.source!r}")


LOADERS: dict[str, Loader] = {
    kinds.GROUND_YAML: _ground_yaml,
    kinds.GROUND_NPZ: _ground_npz,
    kinds.GOAL_YAML: _goal_yaml,
    kinds.GOAL_NPZ: _goal_npz,
    kinds.SHARDED: _sharded,
    kinds.LIFTED: _lifted,
}
"""The loader of each kind of rule file (:data:`csql_sim.core.files.kinds.KINDS`)."""


def load_policy(path: str | os.PathLike | None, n: int | None = None, progress: bool = False) -> Policy:
    """The policy of a rule file from ``csql-sim train`` (any kind), or BFS when ``path`` is None.

    Args:
        path: a rule-base file (YAML or npz, index or goal form), a sharded rule base's
            directory, a lifted Q-classifier file (any n <= 26), or None for the BFS planner.
        n: the number of blocks the caller expects (checked against the rule file's
            header before its classifiers are parsed).
        progress: show a bar while a large rule file is parsed.

    Past six blocks (``n`` > 6) only a lifted file will do: BFS and ground rule files,
    which enumerate the world, are refused in one line.

    Raises:
        CsqlError: if the file is missing, corrupt, foreign, or for another number of blocks.
    """
    large = n is not None and n > MAX_BLOCKS
    if path is None:
        if large:
            raise CsqlError(f"BFS enumerates every state ({count_text(state_count(n))} at {n} blocks) and plans "
                            f"only up to {MAX_BLOCKS} blocks; {LIFTED_HINT}")
        return BfsPolicy()
    kind = None
    try:
        found = read_rule_file(path)
        kind = found.kind
        return LOADERS[kind](found, n, progress)
    except CsqlError as exc:
        if large and kind != kinds.LIFTED:  # a ground rule file is for one n <= 6: its header says which
            raise CsqlError(f"{exc}; {LIFTED_HINT}") from None
        raise


def loads_lifted_file(text: str, source: str) -> Policy:
    """A lifted Q-classifier file's policy: a committee, one population over generated features, or the given atoms."""
    doc = read_versioned_json(text, source, LIFTED_Q_FORMAT, (LIFTED_Q_VERSION, COMMITTEE_VERSION),
                              LiftedPolicyError)
    if doc["version"] == COMMITTEE_VERSION:
        return committee_from_doc(doc, source)
    if "members" in doc:
        raise LiftedPolicyError(f"{source}: 'members' (a committee) needs version {COMMITTEE_VERSION}")
    return feature_policy_from_doc(doc, source) if "domain" in doc else loads_lifted_policy(text, source)
