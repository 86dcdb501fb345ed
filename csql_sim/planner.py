"""Breadth-first optimal planner over the world model: the yardstick for learned plans."""

from __future__ import annotations

import functools
from collections import deque

from csql_sim.world import Action, BlocksWorld, State, WorldError


class NoPlanError(WorldError):
    """No plan exists (cannot happen in the blocks world, but named for callers)."""


@functools.cache
def _distances_to(n: int, goal: int) -> tuple[int, ...]:
    """Optimal plan length from every state to ``goal`` (BFS on the reversed graph)."""
    world = BlocksWorld.of(n)
    preds: list[list[int]] = [[] for _ in world.states]
    for s, row in enumerate(world.next_state):
        for nxt in row:
            if nxt >= 0:
                preds[nxt].append(s)
    dist = [-1] * len(world.states)
    dist[goal] = 0
    queue = deque([goal])
    while queue:
        s = queue.popleft()
        for p in preds[s]:
            if dist[p] < 0:
                dist[p] = dist[s] + 1
                queue.append(p)
    return tuple(dist)


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


class BfsPolicy:
    """The policy interface backed by the BFS planner: the optimal next action."""

    name = "bfs"
    blocks: int | None = None

    def act(self, state: State, goal: State) -> Action | None:
        """The first action of an optimal plan from ``state``, or None at the goal."""
        choices = optimal_actions(state, goal)
        return choices[0] if choices else None
