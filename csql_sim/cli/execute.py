"""Subcommand ``execute``: any planner's plan (an IPC plan file), a rule base or BFS on the simulated arm."""

from __future__ import annotations

import argparse
import sys

from csql_sim.cli.args import (
    RULES_BUILTIN_HELP,
    DeprecatedAlias,
    add_json,
    add_planner,
    add_quiet,
    add_seed,
    add_video_options,
    command_parser,
    path_arg,
    rules_arg,
    show_progress,
    video_options,
)
from csql_sim.cli.output import emit
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import Outputs


def settle_source(args: argparse.Namespace) -> None:
    """Exactly one source of actions: ``--plan FILE``, or ``--planner`` (``rules`` with ``--rules FILE``)."""
    if args.plan is not None:
        if args.rules is not None or args.planner is not None:
            raise CsqlError("--plan FILE is the plan; do not give --rules or --planner with it")
        return
    args.planner = args.planner or ("rules" if args.rules is not None else None)
    if args.planner is None:
        raise CsqlError("give --plan FILE, --rules FILE or --planner bfs|gn1|gn2")
    if (args.planner == "rules") != (args.rules is not None):
        raise CsqlError("--planner rules needs --rules FILE" if args.rules is None else
                        f"--planner {args.planner} does not read --rules {args.rules!r}; give one of them")


def declare_execute(args: argparse.Namespace, outputs: Outputs) -> None:
    """``--out`` (the video) and its provenance sidecar ``<video>.json`` (``--json FILE`` is added by the caller)."""
    settle_source(args)
    outputs.input(args.problem, "PDDL problem")
    outputs.input(args.domain, "PDDL domain")
    outputs.input(args.plan, "plan file")
    outputs.input(args.rules, "rule file")
    if args.video is not None:
        from csql_sim.jobs.render import sidecar_path

        video_options(args).check(args.video)
        sidecar = sidecar_path(args.video)
        outputs.file(args.video, "video file", "video")
        outputs.file(sidecar, "video provenance", "json")


def cmd_execute(args: argparse.Namespace) -> int:
    """Check the plan symbolically, run it closed-loop on the arm, report per step; 0 reached, 1 not."""
    from csql_sim.api import execute
    from csql_sim.api.planning import path_source

    planner = None if args.planner == "rules" else args.planner
    result = execute(path_source(args.problem), path_source(args.plan), path_source(args.domain), video=args.video,
                     rules=args.rules, planner=planner, seed=args.seed, perception=args.perception,
                     perturb=args.perturb, progress=show_progress(args), video_options=video_options(args)).report
    emit(args, result.to_dict(), result.lines)
    if result.video is not None:
        print(f"wrote {result.video} (provenance in {result.video}.json)", file=sys.stderr)
    return 0 if result.reached else 1


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``execute`` to the subparsers."""
    p = command_parser(sub, "execute", "run a PDDL problem's plan (Fast Downward, pyperplan, ...), a rule base, "
                       "BFS or GN1 on the simulated arm; success from perception",
                       "csql-sim execute --problem p.pddl --plan p.plan --out p.mp4")
    p.add_argument("--problem", type=path_arg, required=True,
                   help="a blocks-world PDDL problem (objects sorted by name are cubes A, B, ...; 2..30)")
    p.add_argument("--domain", type=path_arg,
                   help="here its PDDL domain (optional): the 4-operator blocks domain or a move variant")
    p.add_argument("--plan", type=path_arg,
                   help="an IPC plan file: one action per line, e.g. (unstack a b); ';' starts a comment")
    p.add_argument("--rules", type=rules_arg,
                   help="a rule base from 'csql-sim train' (or lifted rules) instead of a plan" + RULES_BUILTIN_HELP)
    add_planner(p)
    p.add_argument("--out", dest="video", type=path_arg, metavar="V",
                   help="write the episode's video (.mp4 or .gif; see the video options) and its provenance <V>.json")
    p.add_argument("--video", dest="video", type=path_arg, metavar="V", action=DeprecatedAlias, new="--out V",
                   help="the same as --out V (deprecated: goes in 0.3.0)")
    p.add_argument("--perception", choices=("pose", "camera"), default="pose", help="perception mode (default pose)")
    p.add_argument("--perturb", action="store_true", help="jitter the start, nudge a cube, drop a carried cube")
    add_seed(p, "episode seed")
    add_video_options(p)
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_execute, declare=declare_execute)


__all__ = ["register"]
