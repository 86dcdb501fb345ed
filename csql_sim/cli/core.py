"""Subcommands of the symbolic core: ``states``, ``rules`` and ``plan`` (its path: :mod:`csql_sim.cli.plan`)."""

from __future__ import annotations

import argparse

from csql_sim.cli.args import (
    RULES_BUILTIN_HELP,
    DeprecatedAlias,
    add_json,
    add_planner,
    add_quiet,
    blocks_arg,
    blocks_help,
    command_parser,
    large_blocks_arg,
    path_arg,
    rules_arg,
    seed_arg,
)
from csql_sim.cli.output import emit
from csql_sim.cli.plan import cmd_plan, declare_plan
from csql_sim.cli.plan_problem import optimum_budget_arg
from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.files.pddl_import import MAX_PLANNED_BLOCKS
from csql_sim.core.state.message import (
    format_state_message,
)
from csql_sim.core.state.world import BlocksWorld
from csql_sim.infra.errors import CsqlError


# ------------------------------------------------------------------ states
def cmd_states(args: argparse.Namespace) -> int:
    world = BlocksWorld.of(args.blocks)
    rows = [
        {"index": i, "notation": s.notation(), "message": format_state_message(s, i)}
        for i, s in enumerate(world.states)
    ]

    def text() -> list[str]:
        head = f"{len(rows)} states for {args.blocks} blocks (message goal field = the state's own code)"
        return [head, *(f"{r['index']:>5}  {r['notation']:<14} {r['message']}" for r in rows)]

    emit(args, {"blocks": args.blocks, "count": len(rows), "states": rows}, text)
    return 0


# ------------------------------------------------------------------ rules
def cmd_rules(args: argparse.Namespace) -> int:
    rules = r_classifiers(args.blocks)
    rows = [{"kind": c.kind, "condition": c.condition, "action": c.action} for c in rules]
    emit(args, {"blocks": args.blocks, "count": len(rows), "rules": rows},
         lambda: [f"{r['kind']} {r['condition']} {r['action']}" for r in rows])
    return 0


# ------------------------------------------------------------------ plan
def _pairs_arg(text: str) -> str | int:
    from csql_sim.core.model.pairs import parse_pairs

    try:
        return parse_pairs(text)
    except CsqlError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


class _AllPairs(DeprecatedAlias):
    """``plan --all``: the old spelling of ``--pairs all``."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: object,
                 option_string: str | None = None) -> None:  # noqa: D102
        super().__call__(parser, namespace, "all", option_string)


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``states``, ``rules`` and ``plan`` to the subparsers."""
    p = command_parser(sub, "states", "list every state of the n-block world", "csql-sim states --blocks 3")
    p.add_argument("--blocks", type=blocks_arg, default=3, help=blocks_help(2, 6, 3))
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_states)

    p = command_parser(sub, "rules", "print the R-classifiers (Figure 5 for n=3)", "csql-sim rules --blocks 3")
    p.add_argument("--blocks", type=blocks_arg, default=3, help=blocks_help(2, 6, 3))
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_rules)

    p = command_parser(sub, "plan", "plan from a start to a goal configuration, or over many pairs",
                       "csql-sim plan --start CBA --goal BAC")
    p.add_argument("--start", help="start configuration, e.g. CBA (A on B on C), or a state message (with its goal)")
    p.add_argument("--goal", help="goal configuration, e.g. BAC (default: the goal of a state message --start)")
    p.add_argument("--blocks", type=large_blocks_arg,
                   help=blocks_help(2, 26, "from the configuration, or 3 with --pairs",
                                    "; past 6 the states are relational and the planner lifted: gn1, gn2, or lifted "
                                    "--rules"))
    add_planner(p, "up to 6 blocks; gn1, gn2 and lifted rules: any n")
    p.add_argument("--rules", type=rules_arg,
                   help="a rule base from 'csql-sim train' (plan greedily from its Q-classifiers), a sharded rule "
                        "base, or lifted rules from 'csql-sim train-lifted' (any n)" + RULES_BUILTIN_HELP
                        + "; --problem without --planner or --rules plans with builtin")
    p.add_argument("--pairs", type=_pairs_arg, default=None,
                   help="plan every ordered pair of distinct states (all; up to 6 blocks) or a seeded sample of "
                        "K (past 6 blocks drawn uniformly by counting), streamed; print a summary")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed of the --pairs sample (default 0)")
    p.add_argument("--all", dest="pairs", nargs=0, action=_AllPairs, new="--pairs all", help=argparse.SUPPRESS)
    p.add_argument("--plan-out", type=path_arg, default=None,
                   help="also write the plan as an IPC plan file (as Fast Downward writes them; "
                        "'execute --plan' reads it; with --problem in the problem's object and action names); with "
                        "--problems DIR a folder (not DIR) that gets <problem>.plan for each solved problem, the "
                        "names 'evaluate --problems DIR --plans' reads")
    p.add_argument("--problem", type=path_arg, default=None, metavar="FILE",
                   help=f"plan a blocks-world PDDL problem of up to {MAX_PLANNED_BLOCKS:,} objects (full or partial "
                        "goal)")
    p.add_argument("--problems", type=path_arg, default=None, metavar="DIR",
                   help="plan every PDDL problem of a folder: one row each (cost, time, lower bound, optimum)")
    p.add_argument("--domain", type=path_arg, default=None,
                   help="with --problem/--problems: their PDDL domain file (optional; its action names are "
                        "the plan file's)")
    p.add_argument("--optimum-budget", type=optimum_budget_arg, default=None, metavar="SECONDS",
                   help="with --problem/--problems: seconds per task to measure the optimum after planning "
                        "(default 1; 0: not measured)")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_plan, declare=declare_plan, mode_options=_pddl_options, ignored=_pddl_ignored)


PDDL_OPTIONS = ("problem", "problems", "domain", "optimum_budget")
"""``plan``'s options for PDDL problems (``--problem``/``--problems``)."""


def _pddl_ignored(args: argparse.Namespace) -> dict[str, str]:
    """``--optimum-budget`` measures PDDL tasks only."""
    return {"optimum_budget": "--problem FILE or --problems DIR"} if args.problem is None and \
        args.problems is None else {}


def _pddl_options(args: argparse.Namespace) -> tuple[str, ...]:
    """The PDDL options when ``plan`` runs pairs or one plan from configurations (not its parameters there)."""
    return PDDL_OPTIONS if args.problem is None and args.problems is None else ()
