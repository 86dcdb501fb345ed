"""The transition table: a world's states, legal actions and successors as index arrays.

One :class:`TransitionTable` is built per world model (:attr:`WorldModel.table
<csql_sim.core.model.world_model.WorldModel.table>`) by matching and predicting every state
message once, and per n for the true world (:func:`true_table`, the yardstick). The
planner, the environments, the array engine, discovery and evaluation all read the same
arrays instead of building their own graph.
"""

from __future__ import annotations

import functools

import numpy as np

from csql_sim.core.state.world import BlocksWorld

ILLEGAL = -1


class TransitionTable:
    """Successor state index per (state, action) of one world; :data:`ILLEGAL` where not allowed.

    Args:
        n: number of blocks.
        next_state: int32 array of shape (states, actions).

    Attributes:
        n: number of blocks.
        next_state: ``next_state[s, a]``, the successor's index or -1.
        legal: per state, the legal action indices in ascending order.
        predecessors: per state, the states with an action leading to it.
    """

    def __init__(self, n: int, next_state: np.ndarray) -> None:
        self.n = n
        self.next_state = np.asarray(next_state, dtype=np.int32)
        self.next_state.setflags(write=False)

    @property
    def state_count(self) -> int:
        return self.next_state.shape[0]

    @property
    def action_count(self) -> int:
        return self.next_state.shape[1]

    @functools.cached_property
    def legal(self) -> tuple[tuple[int, ...], ...]:
        return tuple(tuple(np.flatnonzero(row >= 0).tolist()) for row in self.next_state)

    @functools.cached_property
    def predecessors(self) -> tuple[tuple[int, ...], ...]:
        preds: list[list[int]] = [[] for _ in range(self.state_count)]
        for s, row in enumerate(self.next_state.tolist()):
            for nxt in row:
                if nxt >= 0:
                    preds[nxt].append(s)
        return tuple(tuple(p) for p in preds)

    @functools.cached_property
    def rows(self) -> list[list[int]]:
        """``next_state`` as nested lists (fast per-step indexing in Python loops; do not modify)."""
        return self.next_state.tolist()


@functools.cache
def true_table(n: int) -> TransitionTable:
    """The true n-block world's table (STRIPS semantics; the yardstick, shared per n)."""
    return TransitionTable(n, np.array(BlocksWorld.of(n).next_state, dtype=np.int32))
