"""The classes of moves of a hand-empty state as arrays: :meth:`RelationTracker.classes` without a loop per block.

:meth:`~csql_sim.core.state.relation_tracker.RelationTracker.classes` lists, in move order, the
first move of every (block, kind, relations) class: for each clear block x its move to the
table (unless it stands there) and its moves onto its clear goal support, onto the first
well-placed and the first misplaced clear block (each other than x, its support and its goal
support), in block order. :func:`class_arrays` gives the same list as three arrays, each
relation computed for every block at once (``above-needed`` by doubling along the supports:
log2 n steps), so that a policy ranks a state of hundreds of blocks in a few array operations.
It is exactly the list of ``classes`` (tested on seeded states move by move).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csql_sim.core.state.state import TABLE

WIDTH = 9
"""Relations per move, in the order of :data:`~csql_sim.core.state.atom_names.ATOMS`."""


@dataclass(frozen=True)
class StateArrays:
    """A hand-empty state towards its target, as the tracker keeps it (every array has one entry per block).

    Attributes:
        sup: each block's support (TABLE = -1).
        above: the block on each block, -1 for none.
        goal: each block's goal support.
        goal_above: the block on each block in the goal, -1 for none.
        placed: well placed.
        stuck: deadlocked.
        cover: in the cover; None where it was not yet found.
        fewest: ``least-stuck`` of each block's move to the table (0/1, -1 where not a mover); None where unknown.
    """

    sup: np.ndarray
    above: np.ndarray
    goal: np.ndarray
    goal_above: np.ndarray
    placed: np.ndarray
    stuck: np.ndarray
    cover: np.ndarray | None
    fewest: np.ndarray | None


def above_needed(a: StateArrays, clear: np.ndarray) -> np.ndarray:
    """``above-needed`` of every block, as :meth:`RelationTracker.above_needed` reads it.

    Some block under it is misplaced with its goal place ready (the table, or a clear
    well-placed block), or well placed and the goal support of a misplaced block.
    """
    n = a.sup.shape[0]
    owner = a.goal_above
    g = a.goal
    gi = np.maximum(g, 0)
    ready = (g == TABLE) | ((g >= 0) & (g != np.arange(n)) & a.placed[gi] & clear[gi])
    cond = np.where(a.placed, (owner >= 0) & ~a.placed[np.maximum(owner, 0)], ready)
    acc = np.append(cond, False)  # entry n: below the table, nothing
    link = np.append(np.where(a.sup >= 0, a.sup, n), n)
    below = link.copy()
    for _ in range(max(1, int(n).bit_length())):  # acc[b]: cond over b and the 2^k - 1 blocks under it
        acc = acc | acc[link]
        link = link[link]
    return acc[below[:n]]


def class_arrays(a: StateArrays) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The blocks, destinations and relations (moves, 9) of the classes of moves, in move order (module docstring).

    ``cover`` and ``least-stuck`` are -1 where ``a`` does not know them (:func:`with_known` fills them in).
    """
    n = a.sup.shape[0]
    clear = a.above < 0
    xs = np.flatnonzero(clear)
    k = len(xs)
    placed_x = a.placed[xs]
    good, bad = xs[placed_x][:3], xs[~placed_x][:3]
    g, s = a.goal[xs], a.sup[xs]
    gi = np.maximum(g, 0)
    to_goal = (g >= 0) & (g != xs) & (g != s) & clear[gi]
    dests = np.stack([np.where(to_goal, g, n), _first_other(good, xs, s, g, n), _first_other(bad, xs, s, g, n)], 1)
    order = np.argsort(dests, axis=1, kind="stable")
    rows = np.arange(k)[:, None]
    dest = np.full((k, 4), TABLE, np.int64)
    dest[:, 1:] = dests[rows, order]
    bits = np.zeros((k, 4, WIDTH), np.int8)
    bits[:, :, 0] = ~placed_x[:, None]
    bits[:, :, 3] = a.stuck[xs][:, None]
    bits[:, :, 4] = above_needed(a, clear)[xs][:, None]
    bits[:, :, 6] = a.stuck.any()
    bits[:, :, 8] = -a.stuck[xs].astype(np.int8)[:, None]  # unknown (-1) where stuck, until with_known
    bits[:, 0, 1], bits[:, 0, 2], bits[:, 0, 5] = g == TABLE, 1, -1
    bits[:, 1:, 1] = order == 0  # the goal support is the first of the three destinations before sorting
    bits[:, 1:, 2] = np.stack([a.placed[gi], np.ones(k, bool), np.zeros(k, bool)], 1)[rows, order]
    valid = np.ones((k, 4), bool)
    valid[:, 0] = s != TABLE
    valid[:, 1:] = dest[:, 1:] < n
    block = np.repeat(xs, 4).reshape(k, 4)
    return with_known(block[valid], dest[valid], bits[valid], a)


def with_known(xs: np.ndarray, ds: np.ndarray, bits: np.ndarray, a: StateArrays
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The classes with ``cover`` and ``least-stuck`` as ``a`` knows them (a copy when it knows either)."""
    if a.cover is None and a.fewest is None:
        return xs, ds, bits
    bits = bits.copy()
    if a.cover is not None:
        bits[:, 8] = a.cover[xs]
    if a.fewest is not None:
        table = ds == TABLE
        bits[table, 5] = a.fewest[xs[table]]
    return xs, ds, bits


def _first_other(group: np.ndarray, xs: np.ndarray, s: np.ndarray, g: np.ndarray, none: int) -> np.ndarray:
    """For each block x, the first of ``group`` other than x, its support and its goal support (``none`` if no such)."""
    if len(group) == 0:
        return np.full(len(xs), none, np.int64)
    y = group[None, :]
    ok = (y != xs[:, None]) & (y != s[:, None]) & (y != g[:, None])
    return np.where(ok.any(1), group[ok.argmax(1)], none)


__all__ = ["WIDTH", "StateArrays", "above_needed", "class_arrays", "with_known"]
