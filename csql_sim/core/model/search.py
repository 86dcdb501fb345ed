"""Symbolic search: BFS distances, the optimal planner and greedy argmax.

Rolling a policy out is :mod:`csql_sim.core.policies.rollout`.

The one place for each of these:

* **distances**: :func:`distances_to` is a breadth-first search backwards from a goal on a
  :class:`~csql_sim.core.model.transition_table.TransitionTable`; on the true world
  (:func:`~csql_sim.core.model.transition_table.true_table`) it is the yardstick every learned
  plan is measured against, independent of any agent's knowledge.
* **the optimal planner**: :func:`distance`, :func:`optimal_actions`, :func:`bfs_plan` and
  :class:`BfsPolicy` (on the true world, or on what a world model's R-classifiers say).
* **the distance matrix** and :func:`count_optimal_greedy`, the pairs where a greedy table's
  action lowers the distance by one.
* **greedy argmax**: :func:`greedy_argmax`, the highest value per key, the first on ties.
"""

from __future__ import annotations

import functools
from collections import deque
from collections.abc import Callable

import numpy as np

from csql_sim.core.model.transition_table import TransitionTable, true_table
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.state.world import Action, BlocksWorld, State, WorldError


class NoPlanError(WorldError):
    """No plan exists (cannot happen in the blocks world, but named for callers)."""


# ---------------------------------------------------------------- distances


def reverse_bfs(preds: tuple[tuple[int, ...], ...], goal: int) -> np.ndarray:
    """Optimal plan length from every state to ``goal`` (-1: unreachable), by BFS on ``preds``."""
    dist = np.full(len(preds), -1, np.int32)
    dist[goal] = 0
    queue = deque([goal])
    while queue:
        s = queue.popleft()
        for p in preds[s]:
            if dist[p] < 0:
                dist[p] = dist[s] + 1
                queue.append(p)
    dist.setflags(write=False)
    return dist


@functools.lru_cache(maxsize=64)
def distances_to(goal: int, table: TransitionTable) -> np.ndarray:
    """Plan lengths from every state to state ``goal`` on ``table`` (read-only, memoized)."""
    return reverse_bfs(table.predecessors, goal)


def true_distances(n: int, goal: int) -> np.ndarray:
    """Optimal plan lengths to ``goal`` in the true n-block world (the yardstick)."""
    return distances_to(goal, true_table(n))


def distance(start: State, goal: State) -> int:
    """The optimal number of actions from ``start`` to ``goal``."""
    check_same_world(start, goal)
    world = BlocksWorld.of(start.n)
    return int(true_distances(start.n, world.state_index(goal))[world.state_index(start)])


def check_same_world(a: State, b: State) -> None:
    if a.n != b.n:
        raise WorldError(f"start has {a.n} blocks but goal has {b.n}")


# ---------------------------------------------------------------- the optimal planner


@functools.lru_cache(maxsize=64)
def distance_list(goal: int, table: TransitionTable) -> list[int]:
    return distances_to(goal, table).tolist()


def _first_optimal(table: TransitionTable, dist: list[int], s: int) -> int:
    """The first action (stable order) of ``s`` that lies on a shortest path; -1 if none."""
    row, want = table.rows[s], dist[s] - 1
    for a in table.legal[s]:
        if dist[row[a]] == want >= 0:
            return a
    return -1


def optimal_actions(state: State, goal: State) -> tuple[Action, ...]:
    """Every legal action of ``state`` that lies on some optimal plan to ``goal``."""
    check_same_world(state, goal)
    world, table = BlocksWorld.of(state.n), true_table(state.n)
    dist = true_distances(state.n, world.state_index(goal))
    s = world.state_index(state)
    if dist[s] == 0:
        return ()
    return tuple(world.actions[a] for a in table.legal[s] if dist[table.next_state[s, a]] == dist[s] - 1)


def bfs_plan(start: State, goal: State) -> tuple[Action, ...]:
    """An optimal plan from ``start`` to ``goal``; ties broken by the stable action order."""
    check_same_world(start, goal)
    table, world = true_table(start.n), BlocksWorld.of(start.n)
    state, goal_index = world.state_index(start), world.state_index(goal)
    choose, steps = bfs_choice(table), []
    while state != goal_index:
        action = choose(state, goal_index)
        steps.append(world.actions[action])
        state = table.rows[state][action]
    return tuple(steps)


def bfs_choice(table: TransitionTable) -> Callable[[int, int], int]:
    """BFS as a choice function over indices (raises NoPlanError where the goal is unreachable)."""

    def choose(s: int, g: int) -> int:
        a = _first_optimal(table, distance_list(g, table), s)
        if a < 0:
            states = BlocksWorld.of(table.n).states
            raise NoPlanError(f"the world model gives no plan from {states[s].notation()} to {states[g].notation()}")
        return a

    return choose


class BfsPolicy:
    """The policy interface backed by breadth-first search: an optimal next action.

    Args:
        world_model: plan on this world model's transition table; None (the default)
            plans on the true world.

    Ties are broken by the stable action order.
    """

    name = "bfs"

    def __init__(self, world_model: WorldModel | None = None) -> None:
        self.world_model = world_model
        self.blocks: int | None = None if world_model is None else world_model.n

    def act(self, state: State, goal: State) -> Action | None:
        """The first action of an optimal plan from ``state``, or None at the goal.

        Raises:
            NoPlanError: when the world model connects ``state`` to no path to ``goal``.
        """
        check_same_world(state, goal)
        world = BlocksWorld.of(state.n)
        s, g = world.state_index(state), world.state_index(goal)
        if s == g:
            return None
        a = self._choice(state.n)(s, g)
        return world.actions[a]

    def action_index(self, state: int, goal: int) -> int:
        """:meth:`act` in state and action indices (the policy must know its n: a world model)."""
        assert self.blocks is not None, "BfsPolicy on the true world: use act(), or policy_choice(policy, n)"
        return self._choice(self.blocks)(state, goal)

    def _choice(self, n: int) -> Callable[[int, int], int]:
        table = true_table(n) if self.world_model is None else self.world_model.table
        return bfs_choice(table)


@functools.lru_cache(maxsize=2)
def distance_matrix(n: int) -> np.ndarray:
    """``D[g, s]``: the optimal plan length from state ``s`` to goal ``g`` (all goals at once)."""
    table = true_table(n)
    return np.array([distances_to(g, table) for g in range(table.state_count)], dtype=np.int16)


def count_optimal_greedy(best: np.ndarray, n: int) -> int:
    """The (state, goal) pairs where a greedy table's action lowers the distance by one, vectorized.

    ``best[state * S + goal]`` is the table. A greedy policy plans a pair optimally when
    its action lowers the distance to the goal by one in every state on the way, so it
    plans every ordered pair optimally exactly when this count is ``S * (S - 1)`` (the
    scaling study's stopping test; for a partial count, :func:`check_pairs` rolls out).
    """
    table = true_table(n)
    count = table.state_count
    dist = distance_matrix(n)
    act = best.reshape(count, count)  # [state, goal]
    states, goals = np.arange(count)[:, None], np.arange(count)[None, :]
    nxt = np.where(act >= 0, table.next_state[states, np.maximum(act, 0)], -1)
    ok = (nxt >= 0) & (dist[goals, np.maximum(nxt, 0)] == dist[goals, states] - 1)
    return int(ok.sum())  # the diagonal never counts: its distance less one is -1


# ---------------------------------------------------------------- greedy argmax


def greedy_argmax(keys: np.ndarray, values: np.ndarray, choices: np.ndarray, size: int) -> np.ndarray:
    """Per key in ``0..size-1``, the choice of the highest value (the first in order on ties); -1 where none.

    The vectorized form of "the action of the strongest matching classifier": ``keys``
    index (state, goal) pairs, ``values`` are the Q-values (or strengths), ``choices`` the
    action indices, all of one length and in classifier-list order.
    """
    order = np.lexsort((np.arange(len(keys)), -values, keys))
    first = np.ones(len(order), bool)
    first[1:] = keys[order][1:] != keys[order][:-1]
    best = np.full(size, -1, np.int8)
    best[keys[order][first]] = choices[order][first]
    return best
