"""Checking a plan against a PDDL problem symbolically, as VAL or unified-planning's validator do.

The problem (and its domain, when given) is read by :func:`csql_sim.core.files.pddl_import.read_problem`
(up to :data:`~csql_sim.core.files.pddl_import.MAX_PLANNED_BLOCKS` objects); the plan file by
:func:`csql_sim.core.files.ipc_plan.read_plan`, in any of the blocks-world vocabularies it reads
(four operators, the move variants, csql-sim's export). The domain is data: its action names
say which steps a plan may use; the preconditions and effects are the STRIPS operators of the
world model (:func:`csql_sim.core.state.world.preconditions`, :func:`~csql_sim.core.state.world.successor`),
which every blocks-world domain shares.

:func:`validate_plan` applies the steps in order. A plan is **valid** when every step is
applicable where it comes and the last state satisfies the goal. Otherwise each error is one
line: the first step whose precondition fails (with the step number, the plan file's line, the
precondition in PDDL form and why it fails; the steps after it are not checked, since the state
they would act on does not exist), or, when every step applies, each goal atom the end state
violates.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass

from csql_sim.core.files.ipc_plan import PlanStep, read_plan, why_not
from csql_sim.core.files.pddl_import import MAX_PLANNED_BLOCKS, BlocksProblem, read_problem
from csql_sim.core.state.world import TABLE, ActionKind, Precondition, State, is_legal, preconditions, successor


@dataclass(frozen=True)
class Validation:
    """The verdict on one plan.

    Attributes:
        valid: every step applies and the goal holds at the end.
        steps: the plan's steps (its action lines).
        applied: how many steps applied before the first that does not (all of them when none fails).
        errors: one line per error (empty when valid).
        end: the state after the steps that applied.
    """

    valid: bool
    steps: int
    applied: int
    errors: tuple[str, ...]
    end: State

    def to_json(self) -> dict:
        """The verdict as JSON (without the end state's internals: its named notation)."""
        return {"valid": self.valid, "steps": self.steps, "applied": self.applied, "errors": list(self.errors),
                "end": self.end.named_notation()}


def precondition_text(pre: Precondition, names: Sequence[str]) -> str:
    """A precondition in PDDL form: ``(clear b3)``, ``(on b1 b2)``, ``(ontable b1)``, ``(holding b1)``..."""
    if pre.what == "held":
        return "(handempty)" if pre.value is None else f"(holding {names[pre.value]})"
    if pre.what == "clear":
        return f"(clear {names[pre.block]})"
    if pre.value == TABLE:
        return f"(ontable {names[pre.block]})"
    return f"(on {names[pre.block]} {names[pre.value]})"


def _step_fault(state: State, step: PlanStep, number: int, names: Sequence[str]) -> str | None:
    """Why ``step`` (a line of one or two actions) cannot be applied in ``state``; None when it can."""
    first = step.actions[0]
    if len(step.actions) == 2 and first.kind is ActionKind.UNSTACK and step.actions[1].target == first.target:
        # a move onto the block it leaves: the domain asks that block to be clear before the move, and it is not
        pre = Precondition("clear", first.target)
        why = f"{names[first.target]} is not clear ({names[first.block]} is on it)"
        return _line(number, step, pre, why, names)
    for action in step.actions:
        if not is_legal(state, action):
            pre = next(p for p in preconditions(action) if not p.holds(state))
            return _line(number, step, pre, why_not(state, action, names), names)
        state = successor(state, action)
    return None


def _line(number: int, step: PlanStep, pre: Precondition, why: str, names: Sequence[str]) -> str:
    return (f"step {number} (line {step.line}) {step.text}: precondition {precondition_text(pre, names)} fails: "
            f"{why}")


def _apply(state: State, step: PlanStep) -> State:
    for action in step.actions:
        state = successor(state, action)
    return state


def validate_plan(problem: BlocksProblem, steps: Sequence[PlanStep]) -> Validation:
    """Apply ``steps`` to the problem's start; the verdict, one line per error (module docstring)."""
    names, state = problem.names, problem.start
    for number, step in enumerate(steps, start=1):
        fault = _step_fault(state, step, number, names)
        if fault is not None:
            return Validation(False, len(steps), number - 1, (fault,), state)
        state = _apply(state, step)
    missed = tuple(f"goal {atom} does not hold after step {len(steps)}" for atom in problem.goal.unsatisfied(state))
    return Validation(not missed, len(steps), len(steps), missed, state)


def validate_plan_file(problem: str | os.PathLike, plan: str | os.PathLike,
                       domain: str | os.PathLike | None = None) -> Validation:
    """Read a problem, its domain (optional) and a plan file, and validate the plan.

    Raises:
        CsqlError: one line naming the file that cannot be read, or the plan line that is not
            an action of the problem (an unknown object or action, a wrong number of arguments).
    """
    bp = read_problem(problem, domain, max_blocks=MAX_PLANNED_BLOCKS)
    return validate_plan(bp, read_plan(plan, bp.index, bp.n, allowed=bp.actions))

