"""Subcommand ``discover``: the agent plays with the blocks and induces its R-classifiers."""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

from csql_sim.cli.args import blocks_arg, positive_int
from csql_sim.errors import CsqlError


def check_writable(path: str | None) -> None:
    """Fail now, not after a long run, if ``path`` cannot be written."""
    if path is None:
        return
    folder = Path(path).resolve().parent
    while not folder.exists():
        folder = folder.parent
    if Path(path).is_dir() or not os.access(folder, os.W_OK):
        raise CsqlError(f"cannot write {path}")


def cmd_discover(args: argparse.Namespace) -> int:
    from csql_sim import rulebase, transition_log
    from csql_sim.discovery import Exploration, discover, report_dict, report_lines
    from csql_sim.files import write_atomic

    for path in (args.out, args.log, args.json):
        check_writable(path)
    meta = {"source": "csql-sim discover", "world": args.world, "seed": args.seed, "perturb": args.perturb,
            "perception": args.perception if args.world == "physical" else None}

    def progress(result) -> None:
        if result.transitions % 100 == 0:
            print(f"\r{result.transitions} transitions, {result.failed} failed", end="", file=sys.stderr)

    result = discover(args.blocks, args.world, args.seed, Exploration(max_transitions=args.transitions),
                      args.perception, args.perturb, None if args.quiet else progress)
    if not args.quiet:
        print(file=sys.stderr)
    for line in report_lines(result):
        print(line)
    meta = {**meta, "transitions": result.transitions, "failed_attempts": result.failed}
    path = rulebase.save(args.out, rulebase.RuleBase(args.blocks, result.rules, meta))
    print(f"wrote {len(result.rules)} R-classifiers to {path}")
    if args.log:
        print(f"wrote {transition_log.save(args.log, result.log, args.blocks)}")
    if args.json:
        print(f"wrote {write_atomic(args.json, json.dumps(report_dict(result, meta), indent=1) + chr(10))}")
    return 0 if result.rules else 1


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``discover`` to the subparsers."""
    p = sub.add_parser("discover", help="explore the blocks with all actions and induce the R-classifiers")
    p.add_argument("--blocks", type=blocks_arg, default=3, help="number of blocks, 2..6 (default 3)")
    p.add_argument("--world", choices=("physical", "symbolic"), default="physical",
                   help="the simulated arm (default) or the STRIPS world")
    p.add_argument("--transitions", type=positive_int, default=50000,
                   help="stop after K transitions at the latest (default 50000)")
    p.add_argument("--perception", choices=("pose", "camera"), default="pose", help="perception mode (physical)")
    p.add_argument("--perturb", action="store_true",
                   help="noise: jittered scenes and nudged cubes (physical), knocked towers (symbolic)")
    p.add_argument("--seed", type=int, default=0, help="seed of the run's one generator (default 0)")
    p.add_argument("--out", default="rules.yaml", help="rule file to write (default rules.yaml)")
    p.add_argument("--log", help="also write every transition as JSON lines")
    p.add_argument("--json", help="also write the report as JSON")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.set_defaults(func=cmd_discover)


__all__ = ["register"]
