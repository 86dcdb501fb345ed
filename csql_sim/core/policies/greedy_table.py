"""The greedy policy of a rule file as a table: one action per (state, goal); :func:`load_policy`.

:class:`GreedyTable` answers exactly what :class:`csql_sim.core.policies.policy.QPolicy` answers (the
action of the Q-classifier with the highest Q-value whose condition is the state
message, the first in list order on ties), but it is built once with numpy from the
rule file's arrays, so a 5-block rule base of 1.8 million Q-classifiers becomes a
policy in seconds. Only the learned Q-classifiers decide; nothing is planned here.
"""

from __future__ import annotations

import os

import numpy as np

from csql_sim.core.files.rulebase import RuleBase, RuleBaseError, is_npz, load
from csql_sim.core.files.rulebase_npz import read_arrays, to_arrays
from csql_sim.core.files.rulebase_shards import is_sharded
from csql_sim.core.model.search import BfsPolicy, greedy_argmax
from csql_sim.core.policies.default_hierarchy import DefaultHierarchy, is_goal_form
from csql_sim.core.policies.lifted_policy import is_lifted_policy, load_lifted_policy
from csql_sim.core.policies.policy import VALUES, NoRuleError, Policy
from csql_sim.core.policies.sharded_policy import ShardedPolicy
from csql_sim.core.state.message import format_state_message, layout
from csql_sim.core.state.message_index import action_indices, base36_column, lookup, state_bodies
from csql_sim.core.state.state_count import state_count
from csql_sim.core.state.world import MAX_BLOCKS, Action, BlocksWorld, State
from csql_sim.infra.errors import CsqlError


class GreedyTable:
    """Best action index per (state, goal) of a rule base; the Policy interface on top.

    Args:
        n: number of blocks.
        best: ``best[state * S + goal]``, the action index, or -1 without a Q-classifier.

    """

    name = "rules"

    def __init__(self, n: int, best: np.ndarray) -> None:
        self.n = self.blocks = n
        self.world = BlocksWorld.of(n)
        self.best = best

    @classmethod
    def from_arrays(cls, n: int, kind: np.ndarray, condition: np.ndarray, action: np.ndarray,
                    q: np.ndarray) -> GreedyTable:
        """Build from the npz form's arrays (``S1`` kinds, ``S{L}`` messages, float64 values).

        ``q`` holds the value greedy selection follows (Q-values, or strengths for a
        bucket-brigade rule base).
        """
        world = BlocksWorld.of(n)
        count, lay = len(world.states), layout(n)
        is_q = np.flatnonzero(kind == b"Q")
        conds = condition[is_q]
        state = lookup(conds, 0, lay.goal_start, state_bodies(n))
        goal = base36_column(conds, lay.goal_start, lay.length)
        acts = lookup(action[is_q], 0, lay.length, action_indices(n))
        ok = (state >= 0) & (goal < count)  # other conditions never match a posted state message
        if (acts[ok] < 0).any():
            bad = action[is_q][ok][acts[ok] < 0][0].decode("ascii", "replace")
            raise CsqlError(f"the rule base holds a malformed action message {bad!r} for {n} blocks")
        return cls(n, greedy_argmax((state * count + goal)[ok], q[is_q][ok], acts[ok], count * count))

    @classmethod
    def from_rulebase(cls, rulebase: RuleBase) -> GreedyTable:
        """Build from a :class:`~csql_sim.core.files.rulebase.RuleBase` (``meta["value"]``: the field, default q)."""
        a = to_arrays(rulebase)
        return cls.from_arrays(rulebase.blocks, a["kind"], a["condition"], a["action"], a[_value(rulebase.meta)])

    @classmethod
    def load(cls, path: str | os.PathLike, blocks: int | None = None, progress: bool = False) -> GreedyTable:
        """Read a rule file (npz arrays directly, YAML through the rule-base loader).

        Args:
            path: the rule file.
            blocks: the number of blocks expected; a YAML file for another number is
                refused from its header, before its classifiers are parsed.
            progress: a bar while a large YAML file is parsed.
        """
        if is_npz(path):
            header, a = read_arrays(path, os.fspath(path), RuleBaseError)
            value = _value(header.get("meta", {}))
            return cls.from_arrays(header["blocks"], a["kind"], a["condition"], a["action"], a[value])
        return cls.from_rulebase(load(path, blocks=blocks, progress=progress))

    def action_index(self, state: int, goal: int) -> int:
        """The greedy action index in state ``state`` for ``goal``, or -1."""
        return int(self.best[state * len(self.world.states) + goal])

    def act(self, state: State, goal: State) -> Action | None:
        """The greedy action; raises NoRuleError if no Q-classifier matches."""
        if state == goal:
            return None
        s, g = self.world.state_index(state), self.world.state_index(goal)
        a = self.action_index(s, g)
        if a < 0:
            message = format_state_message(state, g)
            raise NoRuleError(f"no Q-classifier matches state {message} ({state.notation()})")
        return self.world.actions[a]


def _value(meta: dict) -> str:
    """The field a rule base's greedy policy follows (``QPolicy``'s ``value``)."""
    value = meta.get("value", "q")
    if value not in VALUES:
        raise CsqlError(f"value must be one of {', '.join(VALUES)}, got {value!r}")
    return value


LIFTED_HINT = "past six blocks plan with lifted rules (--rules FILE), which hold for any n, or with --planner gn1"


def load_policy(path: str | os.PathLike | None, n: int | None = None, progress: bool = False) -> Policy:
    """The greedy policy of a rule base from ``csql-sim train``, or BFS when ``path`` is None.

    Args:
        path: a rule-base file, a sharded rule base's directory, a lifted Q-classifier
            file (:mod:`csql_sim.core.policies.lifted_policy`, any n <= 26), or None for the BFS planner.
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
            raise CsqlError(f"BFS enumerates every state ({state_count(n):,} at {n} blocks) and plans only up to "
                            f"{MAX_BLOCKS} blocks; {LIFTED_HINT}")
        return BfsPolicy()
    if is_lifted_policy(path):  # lifted Q-classifiers: any number of blocks (core/lifted_policy.py)
        return load_lifted_policy(path)
    try:
        return _load_ground(path, n, progress)
    except CsqlError as exc:
        if large:  # a ground rule file is for one n <= 6: its header says which, before anything is parsed
            raise CsqlError(f"{exc}; {LIFTED_HINT}") from None
        raise


def _load_ground(path: str | os.PathLike, n: int | None, progress: bool) -> Policy:
    """The greedy policy of a ground rule file: sharded, goal form, or index form (YAML or npz)."""
    if is_sharded(path):  # a directory from goal-sharded training, read shard by shard
        return ShardedPolicy.open(path, n)
    if is_goal_form(path):  # generalized Q-classifiers: the default hierarchy's answers (core/default_hierarchy.py)
        return hierarchy_table(path, n, progress)
    table = GreedyTable.load(path, blocks=n, progress=progress)  # QPolicy's answers as a table, YAML or npz
    if n is not None and table.n != n:
        raise CsqlError(f"rule base {os.fspath(path)!r} is for {table.n} blocks, not {n}")
    return table


def hierarchy_table(path: str | os.PathLike, n: int | None = None, progress: bool = False) -> GreedyTable:
    """A goal-form rule file's default hierarchy (:mod:`csql_sim.core.policies.default_hierarchy`) as a greedy table."""
    hierarchy = DefaultHierarchy.from_rulebase(load(path, blocks=n, progress=progress))
    return GreedyTable(hierarchy.n, hierarchy.decisions().best)
