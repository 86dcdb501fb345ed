"""Subcommand ``pddl``: the world model of a set of R-classifiers as a PDDL domain and problem."""

from __future__ import annotations

import argparse

from csql_sim import __version__
from csql_sim.cli.args import add_domain_rules, add_json, add_quiet, blocks_arg, blocks_help, command_parser, path_arg
from csql_sim.cli.output import emit
from csql_sim.cli.plan import read_task
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import PDDL_HEADER, Outputs


def declare_pddl(args: argparse.Namespace, outputs: Outputs) -> None:
    """The folder, ``domain.pddl`` and (with --start) ``problem.pddl`` in it; ``--domain-rules`` is read."""
    out = outputs.folder(args.out, "PDDL folder")
    outputs.file(out / "domain.pddl", "PDDL domain", "pddl")
    if args.start is not None:
        outputs.file(out / "problem.pddl", "PDDL problem", "pddl")
    outputs.input(args.domain_rules, "domain rule file")


def cmd_pddl(args: argparse.Namespace) -> int:
    from pathlib import Path

    from csql_sim.core.classifiers.r_classifier import r_classifiers
    from csql_sim.core.files.pddl_export import domain_text, problem_text
    from csql_sim.core.files.rulebase import load_r_classifiers
    from csql_sim.infra.files import write_or_keep

    if (args.start is None) != (args.goal is None):
        raise CsqlError("pddl needs both --start and --goal, or neither")
    if args.domain_rules:
        rb = load_r_classifiers(args.domain_rules, args.blocks)
        n, rules = rb.blocks, rb.classifiers
    else:
        n = args.blocks or 3
        rules = r_classifiers(n)
    out = Path(args.out)
    outputs = [(out / "domain.pddl", _headed("domain", domain_text(rules, n)))]
    if args.start is not None:
        start, goal = read_task(args.start, args.goal, n)
        outputs.append((out / "problem.pddl", _headed("problem", problem_text(rules, start, goal))))
    written = write_or_keep(outputs)
    emit(args, {"blocks": n, "files": [str(p) for p in written]}, "wrote " + " and ".join(str(p) for p in written))
    return 0


def _headed(what: str, text: str) -> str:
    """A PDDL file's text after the comment line that marks it as ours (:data:`PDDL_HEADER`)."""
    return f"{PDDL_HEADER} {what}, written by csql-sim {__version__}\n{text}"


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``pddl`` to the subparsers."""
    p = command_parser(sub, "pddl", "write the R-classifiers' world model as PDDL (domain, and a problem)",
                       "csql-sim pddl --start CBA --goal BAC --out task")
    p.add_argument("--blocks", type=blocks_arg, default=None, help=blocks_help(2, 6, "3, or the domain's"))
    add_domain_rules(p, "a rule file whose R-classifiers are the world model written (default: Figure 5 / "
                        "generated; was --domain)")
    p.add_argument("--start", help="start configuration, e.g. CBA (writes problem.pddl with --goal)")
    p.add_argument("--goal", help="goal configuration, e.g. BAC")
    p.add_argument("--out", type=path_arg, required=True, help="folder for domain.pddl and problem.pddl")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_pddl, declare=declare_pddl)


__all__ = ["register"]
