"""``validate``: check a plan file against a PDDL problem symbolically (no arm, no planner).

One line per error (the step, its line, the precondition that fails; or a goal atom that does
not hold at the end). Exit status 0 when the plan is valid, 1 when not, 2 for bad input (a
file that cannot be read, a plan line that names an unknown action or object). The work is
:func:`csql_sim.api.validate`, whose verdict is :mod:`csql_sim.core.files.validate`'s.
"""

from __future__ import annotations

import argparse

from csql_sim.cli.args import add_json, add_quiet, command_parser, path_arg
from csql_sim.cli.output import emit
from csql_sim.core.files.pddl_import import MAX_PLANNED_BLOCKS
from csql_sim.infra.outputs import Outputs


def declare_validate(args: argparse.Namespace, outputs: Outputs) -> None:
    """``validate`` reads a problem, a plan and maybe a domain; none of them may be the ``--json`` file."""
    outputs.input(args.problem, "PDDL problem")
    outputs.input(args.plan, "plan file")
    outputs.input(args.domain, "PDDL domain")


def cmd_validate(args: argparse.Namespace) -> int:
    """``validate`` (module docstring)."""
    from csql_sim.api import validate
    from csql_sim.api.planning import path_source

    verdict = validate(path_source(args.problem), path_source(args.plan), path_source(args.domain)).report
    doc = {"problem": args.problem, "plan": args.plan, "domain": args.domain, **verdict.to_json()}

    def text() -> list[str]:
        if verdict.valid:
            return [f"valid: {verdict.steps} steps reach the goal of {args.problem}"]
        return [*verdict.errors, f"invalid: {len(verdict.errors)} error(s) in {args.plan}"]

    emit(args, doc, text)
    return 0 if verdict.valid else 1


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``validate`` to the subparsers."""
    p = command_parser(sub, "validate", "check a plan file against a PDDL problem symbolically: each failing "
                       "step with the precondition that fails, exit 0 when valid, 1 when not",
                       "csql-sim validate --problem p.pddl --plan p.plan --domain domain.pddl")
    p.add_argument("--problem", type=path_arg, required=True, metavar="FILE",
                   help=f"a blocks-world PDDL problem (up to {MAX_PLANNED_BLOCKS:,} objects)")
    p.add_argument("--plan", type=path_arg, required=True, metavar="FILE",
                   help="an IPC plan file: one action per line, e.g. (unstack a b); ';' starts a comment")
    p.add_argument("--domain", type=path_arg, default=None, metavar="FILE",
                   help="the problem's PDDL domain file (optional; its action names are the ones a plan may use)")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_validate, declare=declare_validate)


__all__ = ["register"]
