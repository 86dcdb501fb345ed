"""Subcommand ``problems``: seeded random blocks-world problems of up to 1,000 blocks, as IPC PDDL."""

from __future__ import annotations

import argparse
import os
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
from csql_sim.sim.world import MAX_TOWER_HEIGHT


def declare_problems(args: argparse.Namespace, outputs: Outputs) -> None:
    """The folder and every file in it (existing files need --overwrite); the count is bounded before any draw."""
    from csql_sim.jobs.problems import drawn_names

    out = outputs.folder(args.out, "problem folder")
    for name in drawn_names(args.distribution, args.blocks, args.count, args.max_height):
        outputs.file(out / name, "PDDL domain" if name == "domain.pddl" else "PDDL problem", "pddl")


def cmd_problems(args: argparse.Namespace) -> int:
    """Draw and write the problems one at a time (memory flat); a failed write stops with one short line."""
    from csql_sim.infra.files import OutputError, write_atomic
    from csql_sim.jobs.problems import iter_drawn_problems

    out = Path(args.out)
    written = []
    for name, text in iter_drawn_problems(args.distribution, args.blocks, args.count, args.seed, args.max_height):
        try:
            written.append(write_atomic(out / name, text))
        except (OSError, OutputError) as exc:
            why = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)[:120]
            raise OutputError(f"cannot write {os.fspath(out / name)!r} ({why}); {len(written)} of the files "
                              f"written before it are complete in {os.fspath(out)!r}") from None
    doc = {"distribution": args.distribution, "blocks": args.blocks, "count": args.count, "seed": args.seed,
           "max_height": args.max_height,
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
    p.add_argument("--count", type=positive_int, default=1,
                   help="problems per size (default 1; at most 10,000 problems in all)")
    p.add_argument("--max-height", type=positive_int, default=None, metavar="H",
                   help="tall-towers only: draw only tasks whose start and goal towers are at most H high (pairs "
                        "drawn until one fits, from the same generator; the arm builds towers of at most "
                        f"{MAX_TOWER_HEIGHT})")
    add_seed(p, "seed of the one generator that draws every problem")
    p.add_argument("--out", type=path_arg, required=True, help="folder for domain.pddl and the problems")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_problems, declare=declare_problems)


__all__ = ["register"]
