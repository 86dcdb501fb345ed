"""Subcommand ``problems``: seeded random blocks-world problems of up to 1,000 blocks, as IPC PDDL."""

from __future__ import annotations

import argparse
from pathlib import Path

from csql_sim.cli.args import (
    add_json,
    add_quiet,
    add_seed,
    blocks_help,
    command_parser,
    drawn_blocks_arg,
    path_arg,
    positive_int,
    sizes_type,
)
from csql_sim.cli.output import emit
from csql_sim.core.files.pddl_import import MAX_DRAWN_BLOCKS
from csql_sim.core.model.task_draws import DISTRIBUTIONS
from csql_sim.infra.outputs import Outputs


def _files(args: argparse.Namespace) -> list[tuple[str, str]]:
    from csql_sim.jobs.problems import drawn_problems

    if not hasattr(args, "_drawn"):
        args._drawn = drawn_problems(args.distribution, args.blocks, args.count, args.seed)
    return args._drawn


def declare_problems(args: argparse.Namespace, outputs: Outputs) -> None:
    """The folder and every file in it (existing files need --overwrite)."""
    out = outputs.folder(args.out, "problem folder")
    for name, _ in _files(args):
        outputs.file(out / name, "PDDL domain" if name == "domain.pddl" else "PDDL problem", "pddl")


def cmd_problems(args: argparse.Namespace) -> int:
    from csql_sim.infra.files import write_or_keep

    out = Path(args.out)
    written = write_or_keep([(out / name, text) for name, text in _files(args)])
    doc = {"distribution": args.distribution, "blocks": args.blocks, "count": args.count, "seed": args.seed,
           "written": [str(p) for p in written]}
    emit(args, doc, f"wrote {len(written)} files to {out} (domain.pddl and {len(written) - 1} problems)")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``problems`` to the subparsers."""
    p = command_parser(sub, "problems", "write seeded random blocks-world problems (objects b1..bN) as IPC PDDL",
                       "csql-sim problems --distribution tall-towers --blocks 25,50 --count 30 --out tasks")
    p.add_argument("--distribution", choices=sorted(DISTRIBUTIONS), default="tall-towers",
                   help="tall-towers: a random order of the blocks cut after each with probability 1/10 (towers "
                        "about 10 high); uniform: every configuration equally likely (default tall-towers)")
    p.add_argument("--blocks", type=sizes_type(drawn_blocks_arg), default=[25],
                   help=blocks_help(2, MAX_DRAWN_BLOCKS, 25, "; a list such as 25,50,100 gives each size"))
    p.add_argument("--count", type=positive_int, default=1, help="problems per size (default 1)")
    add_seed(p, "seed of the one generator that draws every problem")
    p.add_argument("--out", type=path_arg, required=True, help="folder for domain.pddl and the problems")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_problems, declare=declare_problems)


__all__ = ["register"]
