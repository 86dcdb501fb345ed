"""The greedy policy of a rule base as a table: one action per (state, goal).

:class:`GreedyTable` answers exactly what :class:`csql_sim.core.policy.QPolicy` answers (the
action of the Q-classifier with the highest Q-value whose condition is the state
message, the first in list order on ties), but it is built once with numpy from the
rule file's arrays, so a 5-block rule base of 1.8 million Q-classifiers becomes a
policy in seconds. Only the learned Q-classifiers decide; nothing is planned here.
"""

from __future__ import annotations

import functools
import os

import numpy as np

from csql_sim.core.message import DIGITS, format_action_message, format_state_message, layout
from csql_sim.core.policy import NoRuleError
from csql_sim.core.world import Action, BlocksWorld, State
from csql_sim.infra.errors import CsqlError

NONE = -1


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
        state = _lookup(conds, 0, lay.goal_start, _state_bodies(n))
        goal = _base36(conds, lay.goal_start, lay.length)
        acts = _lookup(action[is_q], 0, lay.length, _action_messages(n))
        ok = (state >= 0) & (goal < count)  # other conditions never match a posted state message
        if (acts[ok] < 0).any():
            bad = action[is_q][ok][acts[ok] < 0][0].decode("ascii", "replace")
            raise CsqlError(f"the rule base holds a malformed action message {bad!r} for {n} blocks")
        key = (state * count + goal)[ok]
        order = np.lexsort((np.arange(len(key)), -q[is_q][ok], key))
        first = np.ones(len(order), bool)
        first[1:] = key[order][1:] != key[order][:-1]
        best = np.full(count * count, NONE, np.int8)
        best[key[order][first]] = acts[ok][order][first]
        return cls(n, best)

    @classmethod
    def from_rulebase(cls, rulebase) -> GreedyTable:
        """Build from a :class:`~csql_sim.core.rulebase.RuleBase` (``meta["value"]`` names the field, default q)."""
        from csql_sim.core.rulebase_npz import to_arrays

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
        from csql_sim.core.rulebase import RuleBaseError, is_npz, load

        if is_npz(path):
            from csql_sim.core.rulebase_npz import read_arrays

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


@functools.cache
def _state_bodies(n: int) -> dict[bytes, int]:
    """State index by message body (everything before the goal code, action slot 0)."""
    lay = layout(n)
    return {format_state_message(s, 0)[: lay.goal_start].encode(): i for i, s in enumerate(BlocksWorld.of(n).states)}


@functools.cache
def _action_messages(n: int) -> dict[bytes, int]:
    """Action index by action message."""
    return {format_action_message(a, n).encode(): i for i, a in enumerate(BlocksWorld.of(n).actions)}


def known_state(n: int, conditions: np.ndarray) -> np.ndarray:
    """Which conditions are state messages of n blocks with action slot 0 (vectorized)."""
    lay = layout(n)
    if len(conditions) == 0:
        return np.zeros(0, bool)
    body = _lookup(conditions, 0, lay.goal_start, _state_bodies(n))
    goal = _base36(conditions, lay.goal_start, lay.length)
    return (body >= 0) & (goal < len(BlocksWorld.of(n).states))


def known_action(n: int, actions: np.ndarray) -> np.ndarray:
    """Which actions are action messages of n blocks (vectorized)."""
    if len(actions) == 0:
        return np.zeros(0, bool)
    return _lookup(actions, 0, layout(n).length, _action_messages(n)) >= 0


def _value(meta: dict) -> str:
    """The field a rule base's greedy policy follows (``QPolicy``'s ``value``)."""
    from csql_sim.core.policy import VALUES

    value = meta.get("value", "q")
    if value not in VALUES:
        raise CsqlError(f"value must be one of {', '.join(VALUES)}, got {value!r}")
    return value


def _lookup(messages: np.ndarray, start: int, end: int, table: dict[bytes, int]) -> np.ndarray:
    """Index of each message slice in ``table`` (-1 when absent), looked up once per distinct slice."""
    if len(messages) == 0:
        return np.zeros(0, np.int64)
    part = messages.view("S1").reshape(len(messages), -1)[:, start:end].copy().view(f"S{end - start}").ravel()
    uniq, inverse = np.unique(part, return_inverse=True)
    return np.array([table.get(u, NONE) for u in uniq.tolist()], np.int64)[inverse.ravel()]


def _base36(messages: np.ndarray, start: int, end: int) -> np.ndarray:
    """The base-36 number in columns ``start:end`` of each message (huge when not a number)."""
    if len(messages) == 0:
        return np.zeros(0, np.int64)
    chars = messages.view("u1").reshape(len(messages), -1)[:, start:end]
    digit = np.full(256, 10**9, np.int64)
    for i, ch in enumerate(DIGITS):
        digit[ord(ch)] = digit[ord(ch.lower())] = i
    value = np.zeros(len(messages), np.int64)
    for col in range(end - start):
        value = value * len(DIGITS) + digit[chars[:, col]]
    return value
