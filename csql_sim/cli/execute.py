"""Subcommand ``execute``: any planner's plan (an IPC plan file), a rule base or BFS on the simulated arm."""

from __future__ import annotations

import argparse
import sys

from csql_sim.cli.args import add_json, add_quiet, add_seed, path_arg, show_progress
from csql_sim.cli.output import emit
from csql_sim.infra.outputs import Outputs


def declare_execute(args: argparse.Namespace, outputs: Outputs) -> None:
    """``--video`` and its provenance sidecar ``<video>.json`` (``--json FILE`` is added by the caller); the inputs."""
    outputs.input(args.problem, "PDDL problem")
    outputs.input(args.domain, "PDDL domain")
    outputs.input(args.plan, "plan file")
    outputs.input(args.rules, "rule file")
    if args.video is not None:
        from csql_sim.jobs.execute import VIDEO_FPS, VIDEO_SIZE
        from csql_sim.jobs.render import sidecar_path
        from csql_sim.sim.video import check_video_options

        check_video_options(args.video, *VIDEO_SIZE, VIDEO_FPS)
        sidecar = sidecar_path(args.video)
        outputs.file(args.video, "video file", "video", sidecar=sidecar, option="--video")
        outputs.file(sidecar, "video provenance", "json", option="--video")


def cmd_execute(args: argparse.Namespace) -> int:
    """Check the plan symbolically, run it closed-loop on the arm, report per step; 0 reached, 1 not."""
    from csql_sim.jobs.execute import execute_problem

    result = execute_problem(args.problem, args.domain, plan=args.plan, rules=args.rules, planner=args.planner,
                             seed=args.seed, perception=args.perception, perturb=args.perturb, video=args.video,
                             progress=show_progress(args))
    emit(args, result.to_dict(), result.lines)
    if result.video is not None:
        print(f"wrote {result.video} (provenance in {result.video}.json)", file=sys.stderr)
    return 0 if result.reached else 1


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``execute`` to the subparsers."""
    p = sub.add_parser("execute", help="run a PDDL problem's plan (Fast Downward, pyperplan, ...), a rule base or "
                                       "BFS on the simulated arm; success from perception")
    p.add_argument("--problem", type=path_arg, required=True,
                   help="a blocks-world PDDL problem (objects sorted by name are cubes A, B, ...; at most 6)")
    p.add_argument("--domain", type=path_arg,
                   help="its PDDL domain (optional): the 4-operator blocks domain or a move variant")
    how = p.add_mutually_exclusive_group(required=True)
    how.add_argument("--plan", type=path_arg,
                     help="an IPC plan file: one action per line, e.g. (unstack a b); ';' starts a comment")
    how.add_argument("--rules", type=path_arg, help="a rule base from 'csql-sim train' instead of a plan")
    how.add_argument("--planner", choices=("bfs",), help="plan with breadth-first search instead of a plan file")
    p.add_argument("--video", type=path_arg, metavar="V",
                   help="write the episode's video (.mp4 or .gif, 640x480) and its provenance <V>.json")
    p.add_argument("--perception", choices=("pose", "camera"), default="pose", help="perception mode (default pose)")
    p.add_argument("--perturb", action="store_true", help="jitter the start, nudge a cube, drop a carried cube")
    add_seed(p, "episode seed")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_execute, declare=declare_execute)


__all__ = ["register"]
