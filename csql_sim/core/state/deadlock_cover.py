"""The deadlock cover: a minimal set of table visitors that removes every deadlock.

Every deadlock (a cycle of the deadlock graph, :func:`~csql_sim.core.state.goal_relations.deadlocked`)
needs one of its blocks to visit the table before its final move. A set of such
**table visitors** is enough when the ordering constraints of
:class:`~csql_sim.core.state.goal_relations.Precedences`, with each visitor's moves split into its
table visit and its final move, have no cycle (the events of :func:`events`).

The **cover** of a state (towards a hand-empty goal; a held block counts as standing on the
table) starts from every deadlocked block and drops them one at a time, lowest in its tower
first (ties: block order), whenever the others are still enough. What is left is enough and
minimal: no visitor can be spared. It is a greedy choice made by a fixed rule, not the fewest
visitors (that is the exact optimum of :mod:`csql_sim.core.measure.optimum`, a yardstick that
never plans); the relation ``cover(?x)`` of a move reads whether ?x is in it.

This module is the reference, from scratch; the compiled
:func:`csql_sim.core.state.deadlock_kernel.deadlock_cover` gives the same set for large states.
"""

from __future__ import annotations

from csql_sim.core.state.goal_relations import deadlocked, precedences
from csql_sim.core.state.state import State
from csql_sim.core.state.world import TABLE

Event = tuple[int, str]


def events(state: State, goal: State, visitors: frozenset[int]) -> dict[Event, list[Event]]:
    """The ordering constraints as a graph of events: ``(b, "final")`` and, for a visitor, ``(b, "table")``.

    An edge e -> f says that e must happen before f. ``first(b)`` is b's table visit when b is a
    visitor, else its final move.
    """
    pre = precedences(state, goal)

    def first(b: int) -> Event:
        return (b, "table") if b in visitors else (b, "final")

    out: dict[Event, list[Event]] = {(b, "final"): [] for b in pre.misplaced}
    for b in visitors:
        out[(b, "table")] = [(b, "final")]
    for x, b in pre.on_top:
        out[first(x)].append(first(b))
    for x, b in pre.blocking:
        out[first(x)].append((b, "final"))
    for d, b in pre.below_first:
        out[(d, "final")].append((b, "final"))
    return out


def acyclic(graph: dict[Event, list[Event]]) -> bool:
    """Whether the event graph has no cycle (Kahn's algorithm)."""
    indegree = dict.fromkeys(graph, 0)
    for targets in graph.values():
        for f in targets:
            indegree[f] += 1
    ready = [e for e, k in indegree.items() if k == 0]
    seen = 0
    while ready:
        e = ready.pop()
        seen += 1
        for f in graph[e]:
            indegree[f] -= 1
            if indegree[f] == 0:
                ready.append(f)
    return seen == len(graph)


def deadlock_cover(state: State, goal: State) -> frozenset[int]:
    """The cover (module docstring): every deadlocked block, then dropped lowest first while the rest are enough."""
    if state.held is not None:
        support = list(state.support)
        support[state.held] = TABLE
        state = State(tuple(support))
    height = {b: h for tower in state.towers() for h, b in enumerate(tower)}  # blocks under b
    visitors = set(deadlocked(state, goal))
    for b in sorted(visitors, key=lambda v: (height[v], v)):
        visitors.discard(b)
        if not acyclic(events(state, goal, frozenset(visitors))):
            visitors.add(b)
    return frozenset(visitors)
