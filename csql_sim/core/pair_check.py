"""Plan many (start, goal) pairs and check each plan against the optimum, streaming.

The plans come from a policy over state indices: a rule base's :class:`GreedyTable`
(the learned Q-classifiers alone) or the BFS planner. The optimal lengths, the yardstick,
come from a breadth-first search per goal on the reversed transition graph; with
``pairs="all"`` the pairs are visited goal by goal, so one goal's distances are held at a
time and memory stays bounded for any n.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from csql_sim.core.greedy_table import GreedyTable
from csql_sim.core.pairs import sample_ranks, unrank
from csql_sim.core.planner import reverse_bfs, world_predecessors
from csql_sim.core.world import BlocksWorld


@dataclass(frozen=True)
class PairPlan:
    """One pair's plan.

    Attributes:
        start: start state index.
        goal: goal state index.
        actions: the action indices taken.
        reached: whether the plan reaches the goal.
        reason: why not ("" when reached).
        optimal_length: the BFS distance.

    """

    start: int
    goal: int
    actions: tuple[int, ...]
    reached: bool
    reason: str
    optimal_length: int

    @property
    def optimal(self) -> bool:
        return self.reached and len(self.actions) == self.optimal_length


def distances_to(n: int, goal: int) -> list[int]:
    """Optimal plan length from every state to ``goal`` in the true world (see the planner)."""
    return reverse_bfs(world_predecessors(n), goal)


def _plan(world: BlocksWorld, table: GreedyTable | None, dist: list[int], start: int, goal: int) -> PairPlan:
    """Roll the greedy table (or BFS when ``table`` is None) out from ``start``."""
    state, taken, seen = start, [], {start}
    cap = len(world.states)
    while state != goal:
        if len(taken) >= cap:
            return PairPlan(start, goal, tuple(taken), False, f"step cap {cap} reached", dist[start])
        if table is None:
            a = next(a for a in world.legal[state] if dist[world.next_state[state][a]] == dist[state] - 1)
        else:
            a = table.action_index(state, goal)
            if a < 0:
                why = f"no Q-classifier for {world.states[state].notation()}"
                return PairPlan(start, goal, tuple(taken), False, why, dist[start])
        taken.append(a)
        nxt = world.next_state[state][a]
        if nxt < 0:
            why = f"illegal action {world.actions[a].name()} in {world.states[state].notation()}"
            return PairPlan(start, goal, tuple(taken), False, why, dist[start])
        if nxt in seen:
            return PairPlan(start, goal, tuple(taken), False, f"loop at {world.states[nxt].notation()}", dist[start])
        seen.add(nxt)
        state = nxt
    return PairPlan(start, goal, tuple(taken), True, "", dist[start])


def plan_pairs(n: int, table: GreedyTable | None, pairs: str | int = "all", seed: int = 0) -> Iterator[PairPlan]:
    """Plan every pair (goal by goal) or a seeded sample of ``pairs`` (in rank order)."""
    world = BlocksWorld.of(n)
    count = len(world.states)
    if pairs == "all":
        for goal in range(count):
            dist = distances_to(n, goal)
            for start in range(count):
                if start != goal:
                    yield _plan(world, table, dist, start, goal)
        return
    held: dict[int, list[int]] = {}
    for r in sample_ranks(count, pairs, seed):
        start, goal = unrank(r, count)
        if goal not in held:
            held[goal] = distances_to(n, goal)
        yield _plan(world, table, held[goal], start, goal)
