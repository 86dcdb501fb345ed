"""csql-sim as a unified-planning engine: ``OneshotPlanner(name="csql-sim")`` plans blocks-world problems.

Install the extra (``pip install "csql-sim[up]"``), add the engine to unified-planning's
factory, the way UP adds any engine, then ask for it by name::

    from unified_planning.shortcuts import OneshotPlanner, get_environment

    get_environment().factory.add_engine("csql-sim", "csql_sim.up_engine", "CsqlSimPlanner")
    with OneshotPlanner(name="csql-sim") as planner:
        result = planner.solve(problem)          # result.plan: a SequentialPlan of the problem's actions

(:func:`register` does the ``add_engine`` call; a ``up.ini`` section ``[engine csql-sim]``
with ``module_name = csql_sim.up_engine`` and ``class_name = CsqlSimPlanner`` does it too.)

The problem is written as PDDL by UP's own :class:`~unified_planning.io.PDDLWriter` and read
by :func:`csql_sim.api.planning.read_blocks`; the shipped lifted rules plan it
(:func:`csql_sim.api.plan`), up to
:data:`~csql_sim.core.files.pddl_import.MAX_PLANNED_BLOCKS` blocks, and the plan is mapped
back to the problem's actions and objects (a ``heuristic`` or a ``timeout`` is ignored, with a
warning, as UP asks of planners that do not use them). Its plans are not guaranteed optimal: the
status is ``SOLVED_SATISFICING``. Anything that is not a blocks world (other predicates
or actions, other effects, too many blocks) gets the status ``UNSUPPORTED_PROBLEM``, with
the reason in the result's log; before a plan is returned, UP's own sequential simulator
checks it against the problem's actions, so a domain that only looks like the blocks
world is refused too.
"""

from __future__ import annotations

import re
import time
import warnings
from collections.abc import Callable
from typing import IO, Any

import unified_planning as up
from unified_planning.engines import Engine, LogLevel, LogMessage, PlanGenerationResult, PlanGenerationResultStatus
from unified_planning.engines.mixins import OneshotPlannerMixin
from unified_planning.model import ProblemKind

from csql_sim.infra.errors import CsqlError

ENGINE_NAME = "csql-sim"
"""The engine's name in unified-planning's factory."""


def register(environment: Any = None) -> None:
    """Add the engine to ``environment``'s factory (UP's global environment by default); idempotent."""
    factory = up.environment.get_environment(environment).factory
    if ENGINE_NAME not in factory.engines:
        factory.add_engine(ENGINE_NAME, __name__, CsqlSimPlanner.__name__)


class CsqlSimPlanner(Engine, OneshotPlannerMixin):
    """A one-shot planner for blocks-world problems (the 4-operator domain or its move variants)."""

    def __init__(self, **options: Any) -> None:
        Engine.__init__(self)
        OneshotPlannerMixin.__init__(self)
        unknown = sorted(set(options) - {"rules"})
        if unknown:
            raise up.exceptions.UPUsageError(f"{ENGINE_NAME}: unknown option(s) {', '.join(unknown)}; it takes rules")
        self._rules = options.get("rules")

    @property
    def name(self) -> str:
        return ENGINE_NAME

    @staticmethod
    def supported_kind() -> ProblemKind:
        kind = ProblemKind(version=up.model.problem_kind_versioning.LATEST_PROBLEM_KIND_VERSION)
        kind.set_problem_class("ACTION_BASED")
        kind.set_typing("FLAT_TYPING")
        kind.set_conditions_kind("NEGATIVE_CONDITIONS")
        kind.set_conditions_kind("EQUALITIES")
        kind.set_effects_kind("CONDITIONAL_EFFECTS")  # the one-operator move domain's table
        return kind

    @staticmethod
    def supports(problem_kind: ProblemKind) -> bool:
        return problem_kind <= CsqlSimPlanner.supported_kind()

    @staticmethod
    def satisfies(optimality_guarantee: Any) -> bool:
        return False  # plans are near-optimal, never guaranteed optimal

    def _solve(self, problem: up.model.AbstractProblem, heuristic: Callable | None = None,
               timeout: float | None = None, output_stream: IO[str] | None = None) -> PlanGenerationResult:
        from csql_sim.api import plan

        if heuristic is not None or timeout is not None:
            warnings.warn(f"{ENGINE_NAME} ignores the heuristic and the timeout", stacklevel=3)
        began = time.perf_counter()
        writer = up.io.PDDLWriter(problem)
        try:
            found = plan(writer.get_problem(), _untyped_object(writer.get_domain()), rules=self._rules)
        except CsqlError as exc:
            return self._result(PlanGenerationResultStatus.UNSUPPORTED_PROBLEM, None, str(exc), began)
        if not found.solved:
            return self._result(PlanGenerationResultStatus.UNSOLVABLE_INCOMPLETELY, None, found.reason, began)
        named = _items(writer, problem)
        try:
            actions = [up.plans.ActionInstance(named[step[0].lower()], [named[a.lower()] for a in step[1:]])
                       for step in found.actions]
        except KeyError as exc:
            return self._result(PlanGenerationResultStatus.UNSUPPORTED_PROBLEM, None,
                                f"the plan names {exc.args[0]!r}, which the problem does not have", began)
        sequential = up.plans.SequentialPlan(actions, problem.environment)
        why = _not_applicable(problem, sequential)
        if why:
            return self._result(PlanGenerationResultStatus.UNSUPPORTED_PROBLEM, None,
                                f"not the blocks world's actions: {why}", began)
        return self._result(PlanGenerationResultStatus.SOLVED_SATISFICING, sequential,
                            f"{len(actions)} actions by the {found.planner} rules", began)

    def _result(self, status: PlanGenerationResultStatus, plan: Any, message: str,
                began: float) -> PlanGenerationResult:
        level = LogLevel.INFO if plan is not None else LogLevel.ERROR
        return PlanGenerationResult(status, plan, self.name,
                                    metrics={"engine_internal_time": f"{time.perf_counter() - began:.3f}"},
                                    log_messages=[LogMessage(level, message)])


def _untyped_object(domain: str) -> str:
    """UP's domain text without ``- object`` (UP writes it for untyped parameters, which the pddl package refuses)."""
    return re.sub(r"\s-\s+object(?=[\s)])", "", domain)


def _items(writer: Any, problem: Any) -> dict[str, Any]:
    """The problem's actions and objects by their PDDL names, in lower case (csql-sim reads PDDL without case)."""
    return {writer.get_pddl_name(item).lower(): item for item in [*problem.actions, *problem.all_objects]}


def _not_applicable(problem: Any, plan: Any) -> str:
    """Why UP's sequential simulator finds ``plan`` inapplicable or short of the goal ("" when it is valid)."""
    from unified_planning.engines.sequential_simulator import UPSequentialSimulator

    with UPSequentialSimulator(problem) as simulator:
        state = simulator.get_initial_state()
        for k, step in enumerate(plan.actions, 1):
            if not simulator.is_applicable(state, step):
                return f"step {k} {step} is not applicable"
            state = simulator.apply(state, step)
        return "" if simulator.is_goal(state) else "the plan does not reach the goal"


__all__ = ["ENGINE_NAME", "CsqlSimPlanner", "register"]
