"""The greedy policy of a ground rule file as a table: one action per (state, goal).

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
from csql_sim.core.model.search import greedy_argmax
from csql_sim.core.policies.contract import Policy
from csql_sim.core.policies.policy import VALUES, NoRuleError
from csql_sim.core.state.message import format_state_message, layout
from csql_sim.core.state.message_index import action_indices, base36_column, lookup, state_bodies
from csql_sim.core.state.world import Action, BlocksWorld, State
from csql_sim.infra.errors import CsqlError


class GreedyTable(Policy):
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
            return cls.from_npz(*read_arrays(path, os.fspath(path), RuleBaseError))
        return cls.from_rulebase(load(path, blocks=blocks, progress=progress))

    @classmethod
    def from_npz(cls, header: dict, arrays: dict[str, np.ndarray]) -> GreedyTable:
        """Build from an npz rule file's checked header and arrays (``meta["value"]``: the field, default q)."""
        value = _value(header.get("meta", {}))
        return cls.from_arrays(header["blocks"], arrays["kind"], arrays["condition"], arrays["action"],
                               arrays[value])

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
