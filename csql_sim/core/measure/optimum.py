"""The exact optimal plan length for any n <= 26 (a yardstick for measuring, never for planning).

The count is the tool's: the four operators, a pick and a put are two steps (as BFS
counts on :func:`csql_sim.core.model.search.distance`). It follows the deadlock characterization
of optimal blocks-world planning (Gupta and Nau 1992):

* Between hand-empty states, a plan is a sequence of moves (a pick and the put that
  follows). Some optimal plan moves every misplaced block (:mod:`.goal_relations`) either
  once, straight to its goal place, or twice, to the table and later to its goal place;
  well-placed blocks never move. So the optimum is
  ``2 * (misplaced blocks + the fewest blocks that must visit the table)``.
* A set F of table visitors is enough when the ordering constraints of
  :class:`~csql_sim.core.state.goal_relations.Precedences`, with each block of F split into its
  table visit and its final move, have no cycle. Every cycle lies inside one strongly
  connected component of the deadlock graph, so the fewest visitors are found per
  component by iterative deepening: find a cycle, split one of its blocks, recurse
  (exhaustive, hence exact; the deadlocks of random states are small).
* A held block in the start: the first step puts it on its goal place when that is
  ready, else on the table (:func:`_first_put`). A held block in the goal: the last step
  picks it up, from the table or from where it stands (:func:`_last_picks`).

:func:`optimal_length` equals the BFS distance on every pair at n = 3 and 4 and on seeded
samples at n = 5 and 6 (tests/core/test_optimum.py).
"""

from __future__ import annotations

import time

from csql_sim.core.state.goal_relations import (
    Precedences,
    goal_place_ready,
    precedences,
    strongly_connected,
    well_placed,
)
from csql_sim.core.state.world import Action, ActionKind, State, WorldError, successor


class Component:
    """The ordering constraints inside one strongly connected component, as integer events.

    Event ``b`` is block b's final move (arrival at its goal place), event ``b + n`` its
    table visit; ``first(b)`` is the table visit of a visitor, else the final move.
    """

    def __init__(self, pre: Precedences, members: list[int], n: int) -> None:
        inside = set(members)
        self.members, self.n = members, n
        self.on_top = [(x, b) for x, b in pre.on_top if x in inside and b in inside]
        self.blocking = [(x, b) for x, b in pre.blocking if x in inside and b in inside]
        self.below = [(d, b) for d, b in pre.below_first if d in inside and b in inside]

    def events(self, visitors: frozenset[int]) -> dict[int, list[int]]:
        """The event graph with ``visitors`` split into a table visit and a final move."""
        n = self.n
        edges: dict[int, list[int]] = {b: [] for b in self.members}
        for b in visitors:
            edges[b + n] = [b]
        for x, b in self.on_top:
            edges[x + n if x in visitors else x].append(b + n if b in visitors else b)
        for x, b in self.blocking:
            edges[x + n if x in visitors else x].append(b)
        for d, b in self.below:
            edges[d].append(b)
        return edges

    def splittable(self, cycle: list[int], visitors: frozenset[int]) -> list[int]:
        """The blocks of ``cycle`` among which every set of visitors that cuts it has one.

        Splitting block v keeps the cycle's passage p -> v -> q when it can arrive at the
        table visit (p on v) or both arrive at and leave from the final move (an arrival
        constraint in, a goal-support constraint out). A block whose passage is kept by
        its own constraint types alone can still matter where a neighbouring pair is
        constrained in two ways or a neighbour is already split; those are kept too.
        """
        n = self.n
        kinds = {}
        for name, pairs in (("top", self.on_top), ("arrive", self.blocking), ("below", self.below)):
            for pair in pairs:
                kinds.setdefault(pair, set()).add(name)
        out = set()
        for i, v in enumerate(cycle):
            if v >= n or v in visitors:
                continue
            p, q = cycle[i - 1] % n, cycle[(i + 1) % len(cycle)] % n
            into, out_of = kinds.get((p, v), set()), kinds.get((v, q), set())
            cut = "top" not in into and "below" not in out_of
            if cut or len(into) > 1 or len(out_of) > 1 or p in visitors or q in visitors:
                out.add(v)
        return sorted(out)


class OutOfTime(Exception):
    """The search's deadline passed (:func:`fewest_within`); ``found`` cycles were packed by then."""

    def __init__(self, found: int = 0) -> None:
        super().__init__("deadline passed")
        self.found = found


def _check(deadline: float | None, found: int = 0) -> None:
    if deadline is not None and time.monotonic() > deadline:
        raise OutOfTime(found)


def _cycle(edges: dict[int, list[int]], deadline: float | None = None) -> list[int] | None:
    """A shortest cycle of the event graph (its events in order), or None when it is acyclic.

    Short cycles have few splittable blocks: fewer branches, and more disjoint cycles for
    the lower bound. Breadth-first search from every event for the shortest way back to it,
    only from events on a cycle and only inside the event's strongly connected component
    (a way back never leaves it): the same cycle as searching everywhere, found sooner.
    """
    _check(deadline)
    part = {v: i for i, members in enumerate(strongly_connected(edges)) for v in members}
    cyclic = {part[v] for v in edges if sum(part[w] == part[v] for w in edges[v]) > 0}
    best: list[int] | None = None
    for root in edges:
        _check(deadline)
        home = part[root]
        if home not in cyclic:
            continue
        parent, frontier, level, found = {root: root}, [root], 1, None
        while frontier and found is None and (best is None or level < len(best)):
            nxt = []
            for v in frontier:
                if root in edges[v]:
                    found = v
                    break
                for w in edges[v]:
                    if w not in parent and part[w] == home:
                        parent[w] = v
                        nxt.append(w)
            frontier, level = nxt, level + 1
        if found is not None:
            path = [found]
            while path[-1] != root:
                path.append(parent[path[-1]])
            best = path[::-1]
            if len(best) <= 2:
                return best
    return best


def _packing(comp: Component, visitors: frozenset[int], deadline: float | None = None) -> tuple[int, frozenset[int]]:
    """A lower bound on the visitors still needed, and a set of visitors that is enough.

    Cycles are found one after another, each in the graph with the splittable blocks of
    the earlier ones split; their splittable sets are disjoint and each must be hit, so
    their number is a lower bound, and the union of the sets removes every cycle.
    """
    split, count = set(visitors), 0
    while True:
        try:
            cycle = _cycle(comp.events(frozenset(split)), deadline)
        except OutOfTime:
            raise OutOfTime(count) from None
        if cycle is None:
            return count, frozenset(split)
        split |= set(comp.splittable(cycle, frozenset(split)))
        count += 1


def _search(comp: Component, visitors: frozenset[int], best: list[int], seen: set[frozenset[int]],
            deadline: float | None = None) -> None:
    """Branch and bound: split one splittable block of a cycle at a time; prune by :func:`_packing`.

    Any set that removes the cycle found must split one of its splittable blocks, so
    trying each of them in turn is exhaustive.
    """
    bound, _ = _packing(comp, visitors, deadline)
    if len(visitors) + bound >= best[0]:
        return
    cycle = _cycle(comp.events(visitors), deadline)
    if cycle is None:
        best[0] = len(visitors)
        return
    for b in comp.splittable(cycle, visitors):
        more = visitors | {b}
        if more not in seen:
            seen.add(more)
            _search(comp, more, best, seen, deadline)


def _fewest(comp: Component) -> int:
    """The fewest visitors that remove every cycle of one component."""
    return fewest_within(comp, None)[0]


def fewest_within(comp: Component, deadline: float | None) -> tuple[int, int]:
    """Lower and upper bounds on the fewest visitors of one component, equal when the search ended in time.

    The lower bound is the root packing's count (as far as it got); the upper bound the
    best set found, or every member (all of them visiting the table always removes every cycle).
    """
    try:
        lower, enough = _packing(comp, frozenset(), deadline)
    except OutOfTime as stop:
        return stop.found, len(comp.members)
    try:
        for b in sorted(enough):  # shrink the packing's set to a minimal one: the first upper bound
            if _cycle(comp.events(enough - {b}), deadline) is None:
                enough -= {b}
    except OutOfTime:
        return lower, len(enough)
    best = [len(enough) + 1]
    try:
        _search(comp, frozenset(), best, set(), deadline)
    except OutOfTime:
        return lower, min(best[0], len(enough))
    found = min(best[0], len(enough))
    return found, found


def fewest_table_visits(pre: Precedences, n: int) -> int:
    """The fewest misplaced blocks that must visit the table (exact; see the module docstring)."""
    graph = pre.graph()
    total = 0
    for members in strongly_connected(graph):
        if len(members) > 1 or members[0] in graph[members[0]]:
            total += _fewest(Component(pre, members, n))
    return total


def optimal_moves(start: State, goal: State) -> int:
    """The optimal number of moves (pick-and-put pairs) between hand-empty states."""
    pre = precedences(start, goal)
    return len(pre.misplaced) + fewest_table_visits(pre, start.n)


def optimal_length(start: State, goal: State) -> int:
    """The optimal number of actions (four operators) from ``start`` to ``goal``; exact for n <= 26."""
    if start.n != goal.n:
        raise WorldError(f"start has {start.n} blocks but goal has {goal.n}")
    if start == goal:
        return 0
    if start.held is not None:
        return 1 + optimal_length(successor(start, _first_put(start, goal)), goal)
    if goal.held is not None:
        return 1 + min(2 * optimal_moves(start, before) for before in _last_picks(start, goal))
    return 2 * optimal_moves(start, goal)


def _first_put(start: State, goal: State) -> Action:
    """The first step from a held block: onto its goal place when that is ready, else onto the table.

    A block put on its ready goal place never moves again and is in nobody's way; put
    anywhere else it must move again, and the table is in nobody's way either.
    """
    h = start.held
    d = goal.support[h]
    if d >= 0 and goal_place_ready(start, goal, well_placed(start, goal), h):
        return Action(ActionKind.STACK, h, d)
    return Action(ActionKind.PUTDOWN, h)


def _last_picks(start: State, goal: State) -> list[State]:
    """The hand-empty goals the goal's held block g is best picked up from, last.

    g on the table, or where it stands in ``start`` when that is a block the goal leaves
    clear (moving g elsewhere than the table costs as much and can be in the way).
    """
    g = goal.held
    out = [successor(goal, Action(ActionKind.PUTDOWN, g))]
    s = start.support[g]
    if s >= 0 and goal.above_of[s] is None:
        out.append(successor(goal, Action(ActionKind.STACK, g, s)))
    return out
