"""``plan --problem P.pddl`` and ``plan --problems DIR``: PDDL problems of any size.

One problem: the plan in the problem's words (``--plan-out`` writes it as an IPC plan
file), the lower bound and the optimum; exit 0 when solved, 1 when not. A folder: one row
per problem (cost, time, lower bound, optimum or "not measured"); a problem not solved or
not readable is a failed row naming its file, and the exit status is 1. Bad options exit 2.
One problem is :func:`csql_sim.api.plan`, a folder :func:`csql_sim.jobs.plan_problems.plan_folder`.
"""

from __future__ import annotations

import argparse
import math

from csql_sim.cli.args import say, show_progress
from csql_sim.cli.output import emit
from csql_sim.cli.plan_view import check_planner, plan_steps
from csql_sim.core.state.relational_message import MAX_LARGE_MESSAGE
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import Outputs
from csql_sim.jobs.plan_problems import ProblemPlan, plan_folder

PROBLEM_OPTIONS = ("start", "goal", "pairs", "blocks")
"""Options that name another task and do not go with --problem/--problems."""


def optimum_budget_arg(text: str) -> float:
    """Argparse type for ``--optimum-budget``: seconds >= 0."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError(f"must be a number of seconds >= 0, got {text!r}")
    return value


def declare_problem(args: argparse.Namespace, outputs: Outputs) -> None:
    """Refuse options that do not go with --problem/--problems; the inputs are never outputs."""
    if args.problem is not None and args.problems is not None:
        raise CsqlError("give --problem FILE or --problems DIR, not both")
    for name in PROBLEM_OPTIONS:
        if getattr(args, name) is not None:
            raise CsqlError(f"--{name} names another task; --problem and --problems read theirs from PDDL")
    if args.problems is not None and args.plan_out is not None:
        raise CsqlError("--plan-out writes the plan of one --problem; with --problems use --json")
    outputs.input(args.problem, "PDDL problem")
    outputs.input(args.domain, "PDDL domain")


def _optimum_text(plan: ProblemPlan) -> str:
    return "not measured" if plan.optimum is None else plan.optimum.text()


def _lower_text(plan: ProblemPlan) -> str:
    return "not measured" if plan.lower_bound is None else str(plan.lower_bound)


def cmd_plan_problem(args: argparse.Namespace) -> int:
    """``plan --problem`` or ``plan --problems`` (module docstring)."""
    if args.domain is not None and args.problem is None and args.problems is None:
        raise CsqlError("--domain goes with --problem FILE or --problems DIR")
    planner = check_planner(args)
    if args.problems is not None:
        return _folder(args, planner)
    from csql_sim.api import plan

    report = plan(args.problem, args.domain, rules=args.rules, planner=planner, optimum_budget=args.optimum_budget,
                  progress=show_progress(args)).report
    return _single(args, report)


def _single(args: argparse.Namespace, plan: ProblemPlan) -> int:
    """Report one problem; 0 when solved."""
    problem = plan.problem_doc
    names = problem.names
    steps = plan_steps(plan.actions, problem.n)
    for step, action in zip(steps, plan.actions, strict=True):
        step["name"] = action.name(names)
    doc = {**plan.row(), "objects": list(names),
           "start": problem.start.named_notation() if problem.n <= MAX_LARGE_MESSAGE else None,
           "goal": problem.goal.atom_texts(), "plan": steps if plan.solved else None,
           "plan_file_lines": list(plan.lines) if plan.solved else None}
    if not plan.solved:
        emit(args, doc)
        say(args, "error", f"{plan.problem}: not solved by {plan.planner}: {plan.reason}")
        return 1
    if args.plan_out is not None:
        from csql_sim.core.files.ipc_plan import write_ipc_plan_lines
        from csql_sim.infra.outputs import PDDL_HEADER

        write_ipc_plan_lines(plan.lines, args.plan_out, header=f"{PDDL_HEADER} plan of {plan.problem} "
                                                              f"({plan.planner}, {len(plan.actions)} actions)")
    emit(args, doc, lambda: [*plan.lines, _summary(plan)])
    return 0


def _summary(plan: ProblemPlan) -> str:
    measured = "" if plan.optimum is None and plan.lower_bound is None else " (measured after planning)"
    return (f"{len(plan.actions)} actions by {plan.planner} in {plan.seconds:.2f} s; lower bound "
            f"{_lower_text(plan)}, optimum {_optimum_text(plan)}{measured}")


def _folder(args: argparse.Namespace, planner: str) -> int:
    from csql_sim.api.planning import policy_maker

    plans = plan_folder(args.problems, args.domain, policy_maker(args.rules, planner, show_progress(args)), planner,
                        args.optimum_budget)
    solved = sum(p.solved for p in plans)
    doc = {"problems": len(plans), "solved": solved, "optimum_budget_s": args.optimum_budget,
           "rows": [p.row() for p in plans]}
    emit(args, doc, lambda: _folder_lines(plans))
    return 0 if solved == len(plans) else 1


def _folder_lines(plans: list[ProblemPlan]) -> list[str]:
    solved = sum(p.solved for p in plans)
    lines = [f"{solved}/{len(plans)} problems solved",
             f"  {'problem':<28} {'blocks':>6} {'cost':>6} {'time s':>7} {'lower':>6}  optimum"]
    for p in plans:
        name = p.problem.rsplit("/", 1)[-1]
        if not p.solved:
            lines.append(f"  {name:<28} {p.blocks if p.blocks is not None else '-':>6} FAILED: {p.reason}")
            continue
        lines.append(f"  {name:<28} {p.blocks:>6} {len(p.actions):>6} {p.seconds:>7.2f} {_lower_text(p):>6}  "
                     f"{_optimum_text(p)}")
    return lines
