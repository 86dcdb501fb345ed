"""``plan --problem P.pddl`` and ``plan --problems DIR``: PDDL problems of any size.

One problem: the plan in the problem's words (``--plan-out`` writes it as an IPC plan
file), the lower bound and the optimum; exit 0 when solved, 1 when not. A folder: one row
per problem (cost, time, lower bound, optimum or "not measured"); a problem not solved or
not readable is a failed row naming its file, and the exit status is 1. Bad options exit 2.
One problem is :func:`csql_sim.api.plan`; a folder streams :func:`csql_sim.jobs.plan_problems.iter_folder`'s
rows with the API's planners (:func:`csql_sim.api.planning.policy_maker`).
"""

from __future__ import annotations

import argparse
import math
import os

from csql_sim.cli.args import say, show_progress
from csql_sim.cli.output import emit
from csql_sim.cli.plan_view import check_planner, plan_steps
from csql_sim.core.state.relational_message import MAX_LARGE_MESSAGE
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import Outputs
from csql_sim.jobs.plan_problems import ProblemPlan, iter_folder

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
    outputs.input(args.problem, "PDDL problem")
    outputs.input_folder(args.problems, "PDDL problem")
    outputs.input(args.domain, "PDDL domain")
    if args.problems is not None and args.plan_out is not None:
        declare_plan_folder(args, outputs)


def declare_plan_folder(args: argparse.Namespace, outputs: Outputs) -> None:
    """``--problems DIR --plan-out OUTDIR``: a ``<problem>.plan`` per problem in OUTDIR, each declared before any work.

    OUTDIR is a folder other than DIR (the problems stay alone in theirs); no existing plan file
    is replaced without ``--overwrite`` (:class:`~csql_sim.infra.outputs.Outputs`).
    """
    from csql_sim.infra.outputs import same_path
    from csql_sim.jobs.execute_batch import plan_file_name, problem_files

    folder = outputs.folder(args.plan_out, "plan folder", option="--plan-out")
    if same_path(folder, args.problems):
        raise CsqlError(f"--plan-out {args.plan_out!r} is the folder of the problems (--problems); name another "
                        "folder for their plan files")
    for path, unreadable in problem_files(args.problems):
        outputs.input(path, "PDDL problem")
        if unreadable is None:
            outputs.file(folder / plan_file_name(path), "plan file", "pddl", option="--plan-out")


def default_to_builtin_rules(args: argparse.Namespace) -> None:
    """No ``--planner`` and no ``--rules``: a PDDL problem plans with the shipped lifted rules (``--rules builtin``).

    They hold for any number of blocks, up to the objects that ``plan --problem`` reads
    (:data:`~csql_sim.core.files.pddl_import.MAX_PLANNED_BLOCKS`); BFS (``--planner bfs``) stops at six.
    """
    if args.planner is None and args.rules is None:
        from csql_sim.infra.assets import builtin_rules_path

        args.rules = os.fspath(builtin_rules_path())


def _optimum_text(plan: ProblemPlan) -> str:
    return "not measured" if plan.optimum is None else plan.optimum.text()


def _lower_text(plan: ProblemPlan) -> str:
    return "not measured" if plan.lower_bound is None else str(plan.lower_bound)


DEFAULT_OPTIMUM_BUDGET = 1.0
"""Seconds per task to measure the optimum after planning, unless ``--optimum-budget`` says."""


def cmd_plan_problem(args: argparse.Namespace) -> int:
    """``plan --problem`` or ``plan --problems`` (module docstring)."""
    if args.optimum_budget is None:
        args.optimum_budget = DEFAULT_OPTIMUM_BUDGET
    if args.domain is not None and args.problem is None and args.problems is None:
        raise CsqlError("--domain goes with --problem FILE or --problems DIR")
    default_to_builtin_rules(args)
    planner = check_planner(args)
    if args.problems is not None:
        return _folder(args, planner)
    from csql_sim.api import plan
    from csql_sim.api.planning import path_source

    report = plan(path_source(args.problem), path_source(args.domain), rules=args.rules, planner=planner,
                  optimum_budget=args.optimum_budget, progress=show_progress(args)).report
    return _single(args, report)


def _single(args: argparse.Namespace, plan: ProblemPlan) -> int:
    """Report one problem; 0 when solved."""
    problem = plan.problem_doc
    names = problem.names
    steps = plan_steps(plan.actions, problem.n, names)
    doc = {**plan.row(), "objects": list(names),
           "start": problem.start.named_notation() if problem.n <= MAX_LARGE_MESSAGE else None,
           "goal": problem.goal.atom_texts(), "plan": steps if plan.solved else None,
           "plan_file_lines": list(plan.lines) if plan.solved else None}
    if not plan.solved:
        emit(args, doc)
        say(args, "error", f"{plan.problem}: not solved by {plan.planner}: {plan.reason}")
        return 1
    if args.plan_out is not None:
        write_plan_file(plan, args.plan_out)
    emit(args, doc, lambda: [*plan.lines, _summary(plan)])
    return 0


def write_plan_file(plan: ProblemPlan, path: str | os.PathLike) -> None:
    """A solved problem's plan as an IPC plan file, in the problem's words, after a comment line that marks it ours."""
    from csql_sim.core.files.ipc_plan import write_ipc_plan_lines
    from csql_sim.infra.outputs import PDDL_HEADER

    write_ipc_plan_lines(plan.lines, path, header=f"{PDDL_HEADER} plan of {plan.problem} "
                                                  f"({plan.planner}, {len(plan.actions)} actions)")


def _plan_writer(args: argparse.Namespace):  # noqa: ANN202 - None or a callable taking a ProblemPlan
    """With ``--plan-out OUTDIR``: a function writing each solved problem's ``<problem>.plan`` there."""
    if args.plan_out is None:
        return None
    from pathlib import Path

    from csql_sim.jobs.execute_batch import plan_file_name

    folder = Path(args.plan_out)
    folder.mkdir(parents=True, exist_ok=True)
    return lambda plan: write_plan_file(plan, folder / plan_file_name(Path(plan.problem)))


def _summary(plan: ProblemPlan) -> str:
    measured = "" if plan.optimum is None and plan.lower_bound is None else " (measured after planning)"
    return (f"{len(plan.actions)} actions by {plan.planner} in {plan.seconds:.2f} s; lower bound "
            f"{_lower_text(plan)}, optimum {_optimum_text(plan)}{measured}")


def _folder(args: argparse.Namespace, planner: str) -> int:
    """Every problem of the folder, each row written as it finishes (text, or ``--json`` to stdout).

    With ``--json`` one object is streamed, ``{"format", "version", "optimum_budget_s", "rows":
    [...], "problems", "solved", "provenance"}``, a row a line, so a stopped run has printed the
    rows done so far; ``--json FILE`` is still renamed into place whole at the end.
    """
    import json

    from csql_sim.api.planning import policy_maker
    from csql_sim.cli.output import command_parameters, json_stream, report_format, with_format
    from csql_sim.infra.provenance import provenance

    write = _plan_writer(args)
    policy_for = policy_maker(args.rules, planner, show_progress(args))  # the API's planners, loaded once per size
    rows = iter_folder(args.problems, args.domain, policy_for, planner, args.optimum_budget)
    plans: list[ProblemPlan] = []
    with json_stream(args) as out:
        if out is not None:
            head = with_format({"optimum_budget_s": args.optimum_budget, "plan_folder": args.plan_out},
                               report_format(args))
            out.write(json.dumps(head)[:-1] + ', "rows": [')
        else:
            print(TABLE_HEAD, flush=True)
        for plan in rows:
            plans.append(plan)
            if write is not None and plan.solved:
                write(plan)
            if out is not None:
                out.write(("" if len(plans) == 1 else ",") + "\n " + json.dumps(plan.row()))
                out.flush()
            else:
                print(_row_line(plan), flush=True)
        solved = sum(p.solved for p in plans)
        if out is not None:
            tail = {"problems": len(plans), "solved": solved, "provenance": provenance(**command_parameters(args))}
            out.write("\n], " + json.dumps(tail)[1:] + "\n")
        else:
            print(f"{solved}/{len(plans)} problems solved")
            if args.plan_out is not None:
                print(f"wrote {solved} plan file(s) to {args.plan_out}")
    return 0 if solved == len(plans) else 1


TABLE_HEAD = f"  {'problem':<28} {'blocks':>6} {'cost':>6} {'time s':>7} {'lower':>6}  optimum"


def _row_line(p: ProblemPlan) -> str:
    name = p.problem.rsplit("/", 1)[-1]
    if not p.solved:
        return f"  {name:<28} {p.blocks if p.blocks is not None else '-':>6} FAILED: {p.reason}"
    return (f"  {name:<28} {p.blocks:>6} {len(p.actions):>6} {p.seconds:>7.2f} {_lower_text(p):>6}  "
            f"{_optimum_text(p)}")
