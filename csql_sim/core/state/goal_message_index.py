"""Goal-form messages of every (state, goal) pair at once, as a numpy array of characters.

Used where a rule base in the goal form is applied to every pair: the default
hierarchy's decisions (:mod:`~csql_sim.core.policies.default_hierarchy`) and the offline compaction.
Row ``state * S + goal`` holds :func:`~csql_sim.core.state.goal_message.format_goal_message` of
that pair (checked against it in the tests). Up to 5 blocks (866 x 866 pairs of 41
characters: 31 MB).
"""

from __future__ import annotations

import functools

import numpy as np

from csql_sim.core.state.goal_message import GOAL_TAG, GoalForm
from csql_sim.core.state.message import BLOCK_FIELD, format_state_message
from csql_sim.core.state.world import BLOCK_NAMES, HAND, TABLE, BlocksWorld, WorldError

MAX_PAIR_BLOCKS = 5


def _supports(n: int) -> np.ndarray:
    """``support[s, i]``: what block i stands on in state s (-1 table, -2 held, else a block)."""
    return np.array([s.support for s in BlocksWorld.of(n).states], np.int64)


def _chars(texts: list[str]) -> np.ndarray:
    return np.frombuffer("".join(texts).encode("ascii"), np.uint8).reshape(len(texts), -1)


def detector_arrays(n: int) -> dict[str, np.ndarray]:
    """Every detector as a bool array ``[state, goal, block]`` (see :mod:`~csql_sim.core.state.goal_message`)."""
    sup = _supports(n)
    count = len(sup)
    s_sup = np.broadcast_to(sup[:, None, :], (count, count, n))
    g_sup = np.broadcast_to(sup[None, :, :], (count, count, n))
    home = s_sup == g_sup
    grounded = s_sup < 0  # on the table or held
    below = np.maximum(s_sup, 0)
    placed = home & grounded
    for _ in range(n):
        placed = home & (grounded | np.take_along_axis(placed, below, axis=2))
    clear = np.array([[s.is_clear(i) for i in range(n)] for s in BlocksWorld.of(n).states])
    goal_below = np.maximum(g_sup, 0)
    support_clear = np.take_along_axis(np.broadcast_to(clear[:, None, :], (count, count, n)), goal_below, axis=2)
    ready = (g_sup == TABLE) | ((g_sup >= 0) & np.take_along_axis(placed, goal_below, axis=2) & support_clear)
    return {"home": home, "placed": placed, "ready": ready}


@functools.lru_cache(maxsize=2)
def pair_messages(form: GoalForm) -> np.ndarray:
    """``uint8 [states * states, form.length]``: the goal-form message of every (state, goal) pair."""
    n = form.n
    if n > MAX_PAIR_BLOCKS:
        raise WorldError(f"every pair's message is built up to {MAX_PAIR_BLOCKS} blocks, not {n}")
    states = BlocksWorld.of(n).states
    count = len(states)
    state_part = _chars([format_state_message(s, 0)[: form.state_end] for s in states])

    def support_char(v: int) -> str:
        return "t" if v == TABLE else "0" if v == HAND else BLOCK_NAMES[v].lower()

    goal_part = _chars([GOAL_TAG + "".join(support_char(v) for v in s.support).ljust(BLOCK_FIELD, "0")
                        + (BLOCK_NAMES[s.held].lower() if s.held is not None else "0") for s in states])
    out = np.full((count, count, form.length), ord("0"), np.uint8)
    out[:, :, : form.state_end] = state_part[:, None, :]
    out[:, :, form.tag_pos: form.goal_held_pos + 1] = goal_part[None, :, :]
    if form.detectors:
        values = detector_arrays(n)
        for name in form.detectors:
            start = form.detector_start(name)
            out[:, :, start: start + n] = np.where(values[name], ord("1"), ord("0"))
    out = out.reshape(count * count, form.length)
    out.setflags(write=False)
    return out
