"""Breadth-first optimal planner: the yardstick for learned plans, and planning on a world model.

:func:`distance`, :func:`optimal_actions` and :func:`bfs_plan` search the true world
(:class:`csql_sim.core.world.BlocksWorld`): they are the yardstick every learned plan is measured
against, independent of any agent's knowledge. :class:`BfsPolicy` plans either on the true
world or, given a :class:`~csql_sim.core.world_model.WorldModel`, on what the R-classifiers say
(for example rules discovered from experience).
"""

from __future__ import annotations

import functools
from collections import deque
from collections.abc import Iterable

from csql_sim.core.message import decode_code, format_state_message, layout, parse_state_message
from csql_sim.core.world import Action, BlocksWorld, State, WorldError
from csql_sim.core.world_model import WorldModel


class NoPlanError(WorldError):
    """No plan exists (cannot happen in the blocks world, but named for callers)."""


def predecessors(successors: Iterable[Iterable[int]]) -> tuple[tuple[int, ...], ...]:
    """The reversed graph: for each state, the states with an action leading to it.

    Args:
        successors: per state index, its successor state indices (negative ones are ignored).

    """
    rows = [list(r) for r in successors]
    preds: list[list[int]] = [[] for _ in rows]
    for s, row in enumerate(rows):
        for nxt in row:
            if nxt >= 0:
                preds[nxt].append(s)
    return tuple(tuple(p) for p in preds)


def reverse_bfs(preds: tuple[tuple[int, ...], ...], goal: int) -> list[int]:
    """Optimal plan length from every state to ``goal`` (-1: unreachable), by BFS on ``preds``."""
    dist = [-1] * len(preds)
    dist[goal] = 0
    queue = deque([goal])
    while queue:
        s = queue.popleft()
        for p in preds[s]:
            if dist[p] < 0:
                dist[p] = dist[s] + 1
                queue.append(p)
    return dist


@functools.cache
def world_predecessors(n: int) -> tuple[tuple[int, ...], ...]:
    """The true n-block world's reversed graph (shared: the world never changes)."""
    return predecessors(BlocksWorld.of(n).next_state)


@functools.cache
def _distances_to(n: int, goal: int) -> tuple[int, ...]:
    """Optimal plan length from every state to ``goal`` in the true world."""
    return tuple(reverse_bfs(world_predecessors(n), goal))


def distance(start: State, goal: State) -> int:
    """The optimal number of actions from ``start`` to ``goal``."""
    _check_same_world(start, goal)
    world = BlocksWorld.of(start.n)
    return _distances_to(start.n, world.state_index(goal))[world.state_index(start)]


def optimal_actions(state: State, goal: State) -> tuple[Action, ...]:
    """Every legal action of ``state`` that lies on some optimal plan to ``goal``."""
    _check_same_world(state, goal)
    world = BlocksWorld.of(state.n)
    dist = _distances_to(state.n, world.state_index(goal))
    s = world.state_index(state)
    if dist[s] == 0:
        return ()
    return tuple(world.actions[a] for a in world.legal[s] if dist[world.next_state[s][a]] == dist[s] - 1)


def bfs_plan(start: State, goal: State) -> tuple[Action, ...]:
    """An optimal plan from ``start`` to ``goal``; ties broken by the stable action order."""
    plan: list[Action] = []
    state = start
    while state != goal:
        choices = optimal_actions(state, goal)
        if not choices:
            raise NoPlanError(f"no plan from {start.notation()} to {goal.notation()}")
        action = choices[0]
        plan.append(action)
        world = BlocksWorld.of(state.n)
        state = world.states[world.next_state[world.state_index(state)][world.action_index(action)]]
    return tuple(plan)


def _check_same_world(a: State, b: State) -> None:
    if a.n != b.n:
        raise WorldError(f"start has {a.n} blocks but goal has {b.n}")


def _model_graph(model: WorldModel) -> tuple[tuple[tuple[int, int], ...], ...]:
    """Per state index: the (action index, next state index) pairs the world model allows."""
    world = BlocksWorld.of(model.n)
    rows = []
    for state in world.states:
        message = format_state_message(state, 0)
        pairs = []
        for action in model.legal_actions(message):
            parsed = parse_state_message(model.predict(message, action), model.n)
            pairs.append((decode_code(action[1 : 1 + layout(model.n).action_width]) - 1,
                          world.state_index(parsed.state)))
        rows.append(tuple(pairs))
    return tuple(rows)


class BfsPolicy:
    """The policy interface backed by breadth-first search: an optimal next action.

    Args:
        world_model: plan on this world model; None (the default) plans on the true world.

    Ties are broken by the stable action order.
    """

    name = "bfs"

    def __init__(self, world_model: WorldModel | None = None) -> None:
        self.world_model = world_model
        self.blocks: int | None = None if world_model is None else world_model.n
        self._graph: tuple[tuple[tuple[int, int], ...], ...] | None = None
        self._preds: tuple[tuple[int, ...], ...] = ()
        self._distances: dict[int, list[int]] = {}

    def act(self, state: State, goal: State) -> Action | None:
        """The first action of an optimal plan from ``state``, or None at the goal.

        Raises:
            NoPlanError: when the world model connects ``state`` to no path to ``goal``.
        """
        if self.world_model is None:
            choices = optimal_actions(state, goal)
            return choices[0] if choices else None
        world = BlocksWorld.of(state.n)
        s, g = world.state_index(state), world.state_index(goal)
        if s == g:
            return None
        dist = self._distances_to(g)
        assert self._graph is not None
        for action, nxt in sorted(self._graph[s]):
            if dist[nxt] == dist[s] - 1 >= 0:
                return world.actions[action]
        raise NoPlanError(f"the world model gives no plan from {state.notation()} to {goal.notation()}")

    def _distances_to(self, goal: int) -> list[int]:
        """Plan lengths to ``goal`` on the world model's graph (-1: unreachable), memoized."""
        if goal not in self._distances:
            if self._graph is None:
                assert self.world_model is not None
                self._graph = _model_graph(self.world_model)
                self._preds = predecessors([nxt for _, nxt in pairs] for pairs in self._graph)
            self._distances[goal] = reverse_bfs(self._preds, goal)
        return self._distances[goal]
