"""Measuring plans of any size: the lower bound and the optimum, each flagged proven or bounded.

Never used to plan: these are yardsticks for the benchmark and the reports.

* :func:`lower_bound`: twice the misplaced blocks (every misplaced block moves at least
  once, a pick and a put), for hand-empty start and goal.
* :func:`bounded_optimum`: the deadlock characterization of :mod:`.optimum` (the optimum is
  ``2 * (misplaced + the fewest table visitors)``), each strongly connected component of
  the deadlock graph solved by its exact branch and bound within a time budget. Where the
  budget runs out the component gives a lower bound (its cycle packing so far) and an
  upper bound (the best set of visitors found, or all its blocks), and the result is
  *bounded*; otherwise it is *proven*. An upper bound known from elsewhere (a plan's
  length) narrows it further.
* :func:`cpsat_optimum` (optional, the ``bench`` extra): the same question as a CP-SAT
  model (OR-Tools), one component at a time: per block a table-visit flag, a time for its
  final move and one for its table visit, and the deadlock graph's precedences between
  first and final moves; minimise the visitors. Proven when CP-SAT proves optimality,
  else bounded by its best bound and its best solution, each narrowed by what the branch
  and bound finds in a tenth of the budget (its cycle packing is often the better lower bound).
* :func:`hitting_set_optimum` (optional, the ``bench`` extra): implicit hitting sets, one
  component at a time. Every cycle of the event graph yields a clause, the blocks whose
  final and first moves it joins (one of them must visit the table, whatever the other
  visitors); a shortest such cycle through each non-visitor is found by a 0-1 breadth-first
  search. CP-SAT finds the fewest blocks that hit the clauses so far (a lower bound); the
  cycles left by that set, and by its greedy repair to an enough set (an upper bound),
  become more clauses, until the fewest blocks leave no cycle: proven. Proves 200-block
  tall towers in seconds where the two above stay bounded.
"""

from __future__ import annotations

import math
import time
from collections import deque
from dataclasses import dataclass

from csql_sim.core.measure.optimum import Component, fewest_within
from csql_sim.core.state.goal_relations import Precedences, precedences, strongly_connected
from csql_sim.core.state.state import State
from csql_sim.core.state.world import WorldError


@dataclass(frozen=True)
class Bound:
    """The optimal plan length (actions) between ``lower`` and ``upper``; proven when they are equal."""

    lower: int
    upper: int
    method: str = "branch and bound"

    @property
    def proven(self) -> bool:
        """Whether the optimum is known exactly."""
        return self.lower == self.upper

    def text(self) -> str:
        """``86 (proven)`` or ``80..90 (bounded)``."""
        return f"{self.lower} (proven)" if self.proven else f"{self.lower}..{self.upper} (bounded)"

    def narrowed(self, upper: int | None) -> Bound:
        """This bound with a known plan length as a further upper bound."""
        if upper is None or upper >= self.upper:
            return self
        if upper < self.lower:
            raise WorldError(f"a plan of {upper} actions is shorter than the proven lower bound {self.lower}")
        return Bound(self.lower, upper, self.method)


def _hand_empty(start: State, goal: State) -> Precedences:
    if start.n != goal.n:
        raise WorldError(f"start has {start.n} blocks but goal has {goal.n}")
    return precedences(start, goal)  # refuses held blocks


def lower_bound(start: State, goal: State) -> int:
    """Twice the misplaced blocks: no plan between hand-empty states is shorter."""
    return 2 * len(_hand_empty(start, goal).misplaced)


def _components(pre: Precedences, n: int) -> list[Component]:
    graph = pre.graph()
    return [Component(pre, members, n) for members in strongly_connected(graph)
            if len(members) > 1 or members[0] in graph[members[0]]]


def bounded_optimum(start: State, goal: State, budget_s: float = 10.0, upper: int | None = None) -> Bound:
    """The optimum by the deadlock characterization, exact unless ``budget_s`` seconds run out (module docstring)."""
    pre = _hand_empty(start, goal)
    deadline = time.monotonic() + budget_s
    low = high = len(pre.misplaced)
    for comp in _components(pre, start.n):
        lo, hi = fewest_within(comp, deadline)
        low, high = low + lo, high + hi
    return Bound(2 * low, 2 * high).narrowed(upper)


def cpsat_available() -> bool:
    """Whether OR-Tools' CP-SAT can be imported (the ``bench`` extra)."""
    try:
        from ortools.sat.python import cp_model  # noqa: F401
    except ImportError:
        return False
    return True


def _cpsat_component(comp: Component, budget_s: float) -> tuple[int, int]:
    """Lower and upper bounds on one component's fewest visitors by CP-SAT (module docstring)."""
    from ortools.sat.python import cp_model

    model = cp_model.CpModel()
    horizon = 2 * len(comp.members)
    visit = {b: model.new_bool_var(f"v{b}") for b in comp.members}
    final = {b: model.new_int_var(0, horizon, f"f{b}") for b in comp.members}
    table = {b: model.new_int_var(0, horizon, f"t{b}") for b in comp.members}
    first = {b: model.new_int_var(0, horizon, f"s{b}") for b in comp.members}
    for b in comp.members:
        model.add(first[b] == table[b]).only_enforce_if(visit[b])
        model.add(first[b] == final[b]).only_enforce_if(visit[b].Not())
        model.add(table[b] + 1 <= final[b]).only_enforce_if(visit[b])
    for x, b in comp.on_top:
        model.add(first[x] + 1 <= first[b])
    for x, b in comp.blocking:
        model.add(first[x] + 1 <= final[b])
    for d, b in comp.below:
        model.add(final[d] + 1 <= final[b])
    model.minimize(sum(visit.values()))
    solver = cp_model.CpSolver()
    solver.parameters.max_time_in_seconds = max(budget_s, 0.01)
    solver.parameters.num_workers = 1
    status = solver.solve(model)
    if status == cp_model.OPTIMAL:
        value = round(solver.objective_value)
        return value, value
    if status == cp_model.FEASIBLE:
        return math.ceil(solver.best_objective_bound - 1e-6), round(solver.objective_value)
    return 0, len(comp.members)


def cpsat_optimum(start: State, goal: State, budget_s: float = 10.0, upper: int | None = None) -> Bound:
    """The optimum by CP-SAT (module docstring); ``budget_s`` is shared by the components in turn."""
    pre = _hand_empty(start, goal)
    deadline = time.monotonic() + budget_s
    low = high = len(pre.misplaced)
    for comp in sorted(_components(pre, start.n), key=lambda c: len(c.members)):
        lo, hi = _cpsat_component(comp, deadline - time.monotonic())
        if lo < hi:
            more_lo, more_hi = fewest_within(comp, time.monotonic() + budget_s / 10)
            lo, hi = max(lo, more_lo), min(hi, more_hi)
        low, high = low + lo, high + hi
    return Bound(2 * low, 2 * high, "CP-SAT").narrowed(upper)


def _cycle_clause(comp: Component, arcs: dict[int, list[int]], b: int,
                  visitors: frozenset[int]) -> frozenset[int] | None:
    """The blocks that must include a visitor to cut a cycle through non-visitor b, or None if there is none.

    A non-visitor c is its two events joined both ways: the arc first(c) -> final(c), which
    every block has, and the back arc final(c) -> first(c), which a visit removes. A cycle
    is cut only by a visitor among the blocks whose back arcs it uses, whatever the other
    visitors: a valid clause. A 0-1 breadth-first search (back arcs weigh 1) from first(b)
    to final(b), the direct arc left out, finds one with the fewest such blocks. ``arcs`` is the
    event graph with every block split (:meth:`Component.events` of all the members).
    """
    n = comp.n
    source, target = b + n, b
    dist, parent, done = {source: 0}, {source: source}, set()
    queue = deque([source])
    while queue and target not in done:
        v = queue.popleft()
        if v in done:
            continue
        done.add(v)
        steps = [(w, 0) for w in arcs[v] if v != source or w != target]
        if v < n and v not in visitors:
            steps.append((v + n, 1))
        for w, weight in steps:
            if w not in dist or dist[v] + weight < dist[w]:
                dist[w], parent[w] = dist[v] + weight, v
                if weight:
                    queue.append(w)
                else:
                    queue.appendleft(w)
    if target not in done:
        return None
    clause, v = {b}, target
    while v != source:
        v, w = parent[v], v
        if w == v + n:
            clause.add(v)
    return frozenset(clause)


def _clauses(comp: Component, arcs: dict[int, list[int]], visitors: frozenset[int]) -> set[frozenset[int]]:
    """A shortest cycle's clause through every non-visitor on a cycle; none when ``visitors`` is enough."""
    found = (_cycle_clause(comp, arcs, b, visitors) for b in comp.members if b not in visitors)
    return {clause for clause in found if clause is not None}


def _greedy_hit(clauses: set[frozenset[int]]) -> set[int]:
    """Blocks that hit every clause, each in turn the one hitting the most (short clauses weigh more)."""
    left, chosen = set(clauses), set()
    while left:
        weight: dict[int, float] = {}
        for clause in left:
            for b in clause:
                weight[b] = weight.get(b, 0.0) + 1 / len(clause)
        pick = max(weight, key=lambda b: weight[b])
        chosen.add(pick)
        left = {clause for clause in left if pick not in clause}
    return chosen


def _repair(comp: Component, arcs: dict[int, list[int]], visitors: frozenset[int],
            pool: set[frozenset[int]], deadline: float) -> frozenset[int]:
    """A minimal enough set of visitors grown greedily from ``visitors`` (all members when out of time).

    Each round hits the cycles found so far; they go into ``pool`` too.
    """
    split = set(visitors)
    while clauses := _clauses(comp, arcs, frozenset(split)):
        if time.monotonic() > deadline:
            return frozenset(comp.members)
        pool |= clauses
        split |= _greedy_hit(clauses)
    for b in sorted(split):  # a new cycle would pass through b's back arc
        if _cycle_clause(comp, arcs, b, frozenset(split - {b})) is None:
            split.discard(b)
    return frozenset(split)


def _hitting_set(members: list[int], pool: set[frozenset[int]], hint: frozenset[int],
                 budget_s: float) -> tuple[int, frozenset[int] | None]:
    """CP-SAT's lower bound on the fewest members that hit every clause, and such a set when proven fewest."""
    from ortools.sat.python import cp_model

    model = cp_model.CpModel()
    visit = {b: model.new_bool_var(f"v{b}") for b in members}
    for clause in pool:
        model.add_bool_or([visit[b] for b in clause])
    for b in members:
        model.add_hint(visit[b], b in hint)
    model.minimize(sum(visit.values()))
    solver = cp_model.CpSolver()
    solver.parameters.max_time_in_seconds = max(budget_s, 0.01)
    solver.parameters.num_workers = 1
    solver.parameters.linearization_level = 2  # clauses into the LP: its bound is what makes this fast
    status = solver.solve(model)
    if status == cp_model.OPTIMAL:
        return round(solver.objective_value), frozenset(b for b in members if solver.value(visit[b]))
    if status == cp_model.FEASIBLE:
        return math.ceil(solver.best_objective_bound - 1e-6), None
    return 0, None


def _hitting_set_component(comp: Component, deadline: float) -> tuple[int, int]:
    """Lower and upper bounds on one component's fewest visitors by implicit hitting sets (module docstring)."""
    arcs = comp.events(frozenset(comp.members))  # every block split: b its final move, b + n its first
    pool: set[frozenset[int]] = set()
    best = _repair(comp, arcs, frozenset(), pool, deadline)
    low, hint = 0, best
    while low < len(best) and time.monotonic() < deadline:
        bound, chosen = _hitting_set(comp.members, pool, hint, deadline - time.monotonic())
        low = max(low, bound)
        if chosen is None:
            break
        new = _clauses(comp, arcs, chosen)
        if not new:
            return len(chosen), len(chosen)
        pool |= new
        repaired = _repair(comp, arcs, chosen | _greedy_hit(new), pool, deadline)
        best, hint = min(best, repaired, key=len), chosen
    return min(low, len(best)), len(best)


def hitting_set_optimum(start: State, goal: State, budget_s: float = 60.0, upper: int | None = None) -> Bound:
    """The optimum by implicit hitting sets (module docstring); ``budget_s`` is shared by the components in turn."""
    pre = _hand_empty(start, goal)
    deadline = time.monotonic() + budget_s
    low = high = len(pre.misplaced)
    for comp in sorted(_components(pre, start.n), key=lambda c: len(c.members)):
        lo, hi = _hitting_set_component(comp, deadline)
        low, high = low + lo, high + hi
    return Bound(2 * low, 2 * high, "hitting set").narrowed(upper)
