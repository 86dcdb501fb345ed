"""Counting the pairs a greedy policy plans optimally, decided exactly on the policy graph.

A greedy table maps each (state, goal) to one action. Its plan for a pair is optimal
when every greedy step on the way lowers the BFS distance to the goal by one. Two counts:

* :func:`count_optimal_pairs` (**optimal pairs**): the pairs whose whole greedy path is
  optimal. Decided per goal on the policy graph, in order of BFS distance: a pair at
  distance d is optimal when its own step lowers the distance and the pair it leads to
  (at distance d - 1) is optimal. Linear in the table's size (one pass over the pairs,
  sorted by distance with a stable radix sort).
* :func:`count_optimal_steps` (**optimal steps**): the pairs whose *first* greedy step
  lowers the distance. It equals the optimal pairs only when it is complete (every pair);
  below that it over-counts (a good first step into a pair that loops).
"""

from __future__ import annotations

import numpy as np

from csql_sim.core.model.search import count_optimal_greedy, distance_matrix
from csql_sim.core.model.transition_table import true_table


def optimal_pair_mask(best: np.ndarray, n: int) -> np.ndarray:
    """``mask[state * S + goal]``: whether the greedy table ``best`` plans the pair optimally.

    Args:
        best: the greedy action per ``state * S + goal`` (-1: none), S the number of states.
        n: number of blocks (2..6).
    """
    table = true_table(n)
    count = table.state_count
    dist = distance_matrix(n).T.reshape(-1)  # [state * S + goal]
    act = np.asarray(best).reshape(-1).astype(np.int64)
    states = np.repeat(np.arange(count, dtype=np.int64), count)
    goals = np.tile(np.arange(count, dtype=np.int64), count)
    nxt = np.where(act >= 0, table.next_state[states, np.maximum(act, 0)], -1).astype(np.int64)
    step_ok = (nxt >= 0) & (dist[np.maximum(nxt, 0) * count + goals] == dist - 1) & (dist > 0)
    follow = np.maximum(nxt, 0) * count + goals  # the pair the greedy step leads to
    ok = np.zeros(count * count, bool)
    order = np.argsort(dist, kind="stable")  # radix sort of small integers: linear
    ends = np.searchsorted(dist[order], np.arange(int(dist.max()) + 2))
    for d in range(1, int(dist.max()) + 1):
        level = order[ends[d]:ends[d + 1]]
        here = step_ok[level]
        if d > 1:
            here &= ok[follow[level]]
        ok[level] = here
    return ok


def count_optimal_pairs(best: np.ndarray, n: int) -> int:
    """The ordered pairs the greedy table ``best`` plans optimally (see the module)."""
    return int(optimal_pair_mask(best, n).sum())


def count_optimal_steps(best: np.ndarray, n: int) -> int:
    """The pairs whose first greedy step lowers the distance by one (see the module; an upper bound)."""
    return count_optimal_greedy(best, n)
