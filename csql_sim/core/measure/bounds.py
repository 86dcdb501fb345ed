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
"""

from __future__ import annotations

import math
import time
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
