"""Relations between a state and a goal: well placed, goal place ready, and the deadlock graph.

These are the derived relations of blocks-world planning (Gupta and Nau 1992), computed
from a state and a goal alone (any n <= 26, :class:`~csql_sim.core.state.state.State`):

* **well placed**: a block stands on its goal support (the table, the hand, or a block)
  and, when that is a block, the block is well placed too. A block that is not well
  placed is **misplaced** and must move at least once.
* **goal place ready**: a block's goal support is the table, or a well-placed block that
  is clear: the block can go there for good.
* **the deadlock graph** (:func:`precedences`): for hand-empty states and goals, an edge
  b -> x between misplaced blocks says that x must leave its place before b can make its
  final move. A cycle is a deadlock: some block in it must visit the table first.
"""

from __future__ import annotations

from dataclasses import dataclass

from csql_sim.core.state.world import TABLE, State, WorldError


def well_placed(state: State, goal: State) -> tuple[bool, ...]:
    """Per block: on its goal support, with everything below it well placed."""
    if state.n != goal.n:
        raise WorldError(f"state has {state.n} blocks but goal has {goal.n}")
    return placed_from(tuple(s == g for s, g in zip(state.support, goal.support, strict=True)), state.support)


def placed_from(home: tuple[bool, ...], support: tuple[int, ...]) -> tuple[bool, ...]:
    """Per block: ``home[b]`` and, when ``support[b]`` is a block, that block placed too (no recursion).

    Each block is settled once, walking down its tower to the first settled block or the
    bottom, then back up: linear in the number of blocks, whatever a tower's height.
    """
    placed: list[bool | None] = [None] * len(support)
    for b in range(len(support)):
        path = []
        while b >= 0 and placed[b] is None:
            path.append(b)
            b = support[b]
        ok = placed[b] if b >= 0 else True
        for c in reversed(path):
            ok = home[c] and ok
            placed[c] = ok
    return tuple(bool(p) for p in placed)


def goal_place_ready(state: State, goal: State, placed: tuple[bool, ...], b: int) -> bool:
    """Whether block b can be put on its goal support for good now (the table, or a clear well-placed block)."""
    d = goal.support[b]
    if d == TABLE:
        return True
    return d >= 0 and placed[d] and state.is_clear(d) and state.held != d


@dataclass(frozen=True)
class Precedences:
    """The ordering constraints between the moves of misplaced blocks (hand-empty state and goal).

    Every misplaced block b has a final move (onto its goal support); a block in the set
    that visits the table also has a first move (onto the table). ``first(b)`` is the table
    visit when there is one, else the final move.

    Attributes:
        misplaced: the misplaced blocks, ascending.
        on_top: ``(x, b)``: x stands directly on b, so first(x) precedes first(b).
        blocking: ``(x, b)``: x stands directly on b's goal support, so first(x) precedes final(b).
        below_first: ``(d, b)``: d is b's misplaced goal support, so final(d) precedes final(b).
    """

    misplaced: tuple[int, ...]
    on_top: tuple[tuple[int, int], ...]
    blocking: tuple[tuple[int, int], ...]
    below_first: tuple[tuple[int, int], ...]

    def graph(self) -> dict[int, set[int]]:
        """The deadlock graph: b -> x when x's first move must precede b's final move (no table visits)."""
        out: dict[int, set[int]] = {b: set() for b in self.misplaced}
        for x, b in (*self.on_top, *self.blocking, *self.below_first):
            out[b].add(x)
        return out


def precedences(state: State, goal: State) -> Precedences:
    """The constraints of :class:`Precedences` (both states hand-empty)."""
    if state.held is not None or goal.held is not None:
        raise WorldError("the deadlock graph is defined for hand-empty states and goals")
    placed = well_placed(state, goal)
    misplaced = tuple(b for b in range(state.n) if not placed[b])
    on_top, blocking, below = [], [], []
    for b in misplaced:
        x = state.above_of[b]
        if x is not None:
            on_top.append((x, b))
        d = goal.support[b]
        if d >= 0:
            top = state.above_of[d]
            if top is not None:
                blocking.append((top, b))
            if not placed[d]:
                below.append((d, b))
    return Precedences(misplaced, tuple(on_top), tuple(blocking), tuple(below))


def strongly_connected(graph: dict[int, set[int]]) -> list[list[int]]:
    """The strongly connected components of ``graph`` (Tarjan, iterative), each sorted."""
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    stack: list[int] = []
    on_stack: set[int] = set()
    out: list[list[int]] = []
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            v, children = work[-1]
            w = next(children, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                elif w in on_stack:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                component = []
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    component.append(w)
                    if w == v:
                        break
                out.append(sorted(component))
    return out


def deadlocked(state: State, goal: State) -> frozenset[int]:
    """The misplaced blocks on a cycle of the deadlock graph (hand-empty state and goal)."""
    graph = precedences(state, goal).graph()
    return frozenset(b for c in strongly_connected(graph) for b in c if len(c) > 1 or b in graph[b])
