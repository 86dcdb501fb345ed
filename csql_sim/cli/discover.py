"""Subcommand ``discover``: the agent plays with the blocks and induces its R-classifiers."""

from __future__ import annotations

import argparse
import sys

from csql_sim.cli.args import (
    add_json,
    add_quiet,
    blocks_arg,
    blocks_help,
    command_parser,
    path_arg,
    positive_int,
    seed_arg,
    show_progress,
)
from csql_sim.cli.output import command_parameters, default_path, emit
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import Outputs

DEFAULT_OUT = "rules.yaml"
MIN_LIFTED_BLOCKS = 3


def declare_discover(args: argparse.Namespace, outputs: Outputs) -> None:
    """The rule file (default ``rules.yaml``, never replaced unless asked) and the optional log."""
    default = default_path(args, "out", DEFAULT_OUT)
    outputs.file(args.out, "rule file", "rules", default=default)
    if args.log is not None:
        outputs.file(args.log, "transition log", "transitions", option="--log")
    if args.lifted is not None:
        if args.blocks < MIN_LIFTED_BLOCKS:
            raise CsqlError(f"--lifted needs --blocks {MIN_LIFTED_BLOCKS} or more: with {args.blocks} blocks "
                            f"the induced conditions are shorter than the schemas (see csql_sim.discovery.lifting)")
        outputs.file(args.lifted, "lifted rule file", "rules", option="--lifted")


def cmd_discover(args: argparse.Namespace) -> int:
    from csql_sim.core.classifiers.lifted_rule import dumps_lifted
    from csql_sim.core.files import rulebase
    from csql_sim.discovery import transition_log
    from csql_sim.discovery.explore import Exploration, report_dict, report_lines
    from csql_sim.discovery.lifting import lift_rules
    from csql_sim.infra.files import write_or_keep
    from csql_sim.infra.provenance import provenance
    from csql_sim.jobs.discover import discover

    meta = {"source": "csql-sim discover", "world": args.world, "seed": args.seed, "perturb": args.perturb,
            "perception": args.perception if args.world == "physical" else None}

    def progress(result) -> None:
        if result.transitions % 100 == 0:
            print(f"\r{result.transitions} transitions, {result.failed} failed", end="", file=sys.stderr)

    shown = show_progress(args)
    result = discover(args.blocks, args.world, args.seed, Exploration(max_transitions=args.transitions),
                      args.perception, args.perturb, progress if shown else None)
    if shown:
        print(file=sys.stderr)
    meta = {**meta, "transitions": result.transitions, "failed_attempts": result.failed}
    outputs = [(args.out, rulebase.dumps(rulebase.RuleBase(args.blocks, result.rules, meta)))]
    if args.log is not None:
        outputs.append((args.log, transition_log.dumps(result.log, args.blocks)))
    lifting = lift_rules(result.rules, args.blocks) if args.blocks >= MIN_LIFTED_BLOCKS else None
    if args.lifted is not None:
        outputs.append((args.lifted, dumps_lifted(lifting.rules, {
            **meta, "induced_from_blocks": args.blocks, "not_lifted": lifting.problems,
            "provenance": provenance(**command_parameters(args))})))
    written = [str(p) for p in write_or_keep(outputs)]
    wrote = f"wrote {len(result.rules)} R-classifiers to {written[0]}" + "".join(f", {p}" for p in written[1:])
    lifted = [] if lifting is None else [f"{len(lifting.rules)} lifted rules:", *(f"  {x}" for x in lifting.lines())]
    doc = {**report_dict(result, meta), "lifted": None if lifting is None else [r.text() for r in lifting.rules],
           "not_lifted": None if lifting is None else lifting.problems, "written": written}
    emit(args, doc, lambda: [*report_lines(result), *lifted, wrote])
    return 0 if result.rules else 1


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``discover`` to the subparsers."""
    p = command_parser(sub, "discover", "explore the blocks with all actions and induce the R-classifiers",
                       "csql-sim discover --world symbolic --out discovered.yaml")
    p.add_argument("--blocks", type=blocks_arg, default=3, help=blocks_help(2, 6, 3))
    p.add_argument("--world", choices=("physical", "symbolic"), default="physical",
                   help="the simulated arm (default) or the STRIPS world")
    p.add_argument("--transitions", type=positive_int, default=50000,
                   help="stop after K transitions at the latest (default 50000)")
    p.add_argument("--perception", choices=("pose", "camera"), default="pose",
                   help="perception mode on the arm (default pose)")
    p.add_argument("--perturb", action="store_true",
                   help="noise: jittered scenes and nudged cubes (physical), knocked towers (symbolic)")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed of the run's one generator (default 0)")
    p.add_argument("--out", type=path_arg, default=None,
                   help=f"rule file to write (default {DEFAULT_OUT}; an existing one is kept unless --overwrite)")
    p.add_argument("--log", type=path_arg, help="also write every transition as JSON lines")
    p.add_argument("--lifted", type=path_arg, default=None,
                   help="also write the lifted rules induced from the discovered ones (JSON; --blocks 3 or more)")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_discover, declare=declare_discover)


__all__ = ["register"]
