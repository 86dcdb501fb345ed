"""State and action messages to indices, vectorized over numpy arrays of message bytes.

Used where many classifiers are read at once: the npz rule-file checks
(:mod:`~csql_sim.core.files.rulebase_npz`) and the greedy table (:mod:`~csql_sim.core.policies.greedy_table`).
"""

from __future__ import annotations

import functools

import numpy as np

from csql_sim.core.state.message import DIGITS, action_messages, format_state_message, layout
from csql_sim.core.state.world import BlocksWorld

NONE = -1


@functools.cache
def state_bodies(n: int) -> dict[bytes, int]:
    """State index by message body (everything before the goal code, action slot 0)."""
    lay = layout(n)
    return {format_state_message(s, 0)[: lay.goal_start].encode(): i for i, s in enumerate(BlocksWorld.of(n).states)}


@functools.cache
def action_indices(n: int) -> dict[bytes, int]:
    """Action index by action message."""
    return {m.encode(): i for i, m in enumerate(action_messages(n))}


def known_state(n: int, conditions: np.ndarray) -> np.ndarray:
    """Which conditions are state messages of n blocks with action slot 0 (vectorized)."""
    lay = layout(n)
    if len(conditions) == 0:
        return np.zeros(0, bool)
    body = lookup(conditions, 0, lay.goal_start, state_bodies(n))
    goal = base36_column(conditions, lay.goal_start, lay.length)
    return (body >= 0) & (goal < len(BlocksWorld.of(n).states))


def known_action(n: int, actions: np.ndarray) -> np.ndarray:
    """Which actions are action messages of n blocks (vectorized)."""
    if len(actions) == 0:
        return np.zeros(0, bool)
    return lookup(actions, 0, layout(n).length, action_indices(n)) >= 0


def lookup(messages: np.ndarray, start: int, end: int, table: dict[bytes, int]) -> np.ndarray:
    """Index of each message slice in ``table`` (-1 when absent), looked up once per distinct slice."""
    if len(messages) == 0:
        return np.zeros(0, np.int64)
    part = messages.view("S1").reshape(len(messages), -1)[:, start:end].copy().view(f"S{end - start}").ravel()
    uniq, inverse = np.unique(part, return_inverse=True)
    return np.array([table.get(u, NONE) for u in uniq.tolist()], np.int64)[inverse.ravel()]


def base36_column(messages: np.ndarray, start: int, end: int) -> np.ndarray:
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
