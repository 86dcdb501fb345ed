"""Subcommands of the physical world: ``render`` and ``evaluate``."""

from __future__ import annotations

import argparse
import os
import sys
from typing import TYPE_CHECKING

from csql_sim.cli.args import add_quiet, blocks_arg, positive_int, seed_arg, show_progress, warn_workers
from csql_sim.cli.core import read_task_for_rules
from csql_sim.errors import CsqlError

if TYPE_CHECKING:
    from csql_sim.sim.executor import EpisodeResult


def pairs_arg(text: str) -> str | int:
    """Argparse type for --pairs: ``all`` or a positive integer."""
    if text.strip().lower() == "all":
        return "all"
    return positive_int(text)


def print_episode(result: EpisodeResult) -> None:
    """Print an episode: verdict, every executed step (message, action, sim time, mismatch), events."""
    verdict = "reached the goal" if result.success else f"FAILED: {result.reason}"
    print(f"{result.start} -> {result.goal}: {verdict} in {result.length} actions "
          f"(optimal {result.optimal_length}), {result.sim_seconds:.2f} s simulated")
    for step in result.steps:
        flag = "" if not step.mismatch else f"   mismatch: predicted {step.predicted}, perceived {step.perceived}"
        print(f"  {step.message}  {step.action:<14} {step.sim_seconds:.2f} s{flag}")
    for event in result.events:
        print(f"  perturbation: {event}")


def cmd_render(args: argparse.Namespace) -> int:
    from csql_sim.sim import check_video_options, load_policy, render_episode

    if not args.start or not args.goal:
        raise CsqlError("render needs --start and --goal")
    check_video_options(args.out, args.width, args.height, args.fps)
    warn_workers(args.workers)
    start, goal = read_task_for_rules(args.start, args.goal, None, args.rules)
    policy = load_policy(args.rules, start.n)
    result, path = render_episode(start, goal, args.out, policy, seed=args.seed, width=args.width,
                                  height=args.height, fps=args.fps, workers=args.workers, perturb=args.perturb,
                                  perception=args.perception, progress=show_progress(args))
    print_episode(result)
    frames = len(result.recording.frames) if result.recording else 0
    print(f"wrote {path} ({frames} frames at {args.fps} fps, {args.width}x{args.height})")
    return 0 if result.success else 1


def cmd_evaluate(args: argparse.Namespace) -> int:
    from csql_sim.evaluate import evaluate, write_json
    from csql_sim.files import check_output_file

    if args.json:
        check_output_file(args.json, "JSON report")
    warn_workers(args.workers)

    report = evaluate(n=args.blocks, pairs=args.pairs, seeds=args.seeds, perturb=args.perturb,
                      workers=args.workers, rules=args.rules, perception=args.perception,
                      progress=show_progress(args))
    print(report.text())
    if args.json:
        path = write_json(report, args.json)
        print(f"wrote {path}", file=sys.stderr)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``render`` and ``evaluate`` to the subparsers."""
    cores = os.cpu_count() or 1
    p = sub.add_parser("render", help="execute a plan on the simulated Panda and write a captioned video")
    p.add_argument("--start", help="start configuration, e.g. CBA (A on B on C); '+X' holds X")
    p.add_argument("--goal", help="goal configuration, e.g. BAC")
    p.add_argument("--rules", help="a rule base from 'csql-sim train' (default: the BFS planner)")
    p.add_argument("--out", default="video.mp4", help="output .mp4 or .gif (default video.mp4)")
    p.add_argument("--width", type=positive_int, default=640, help="frame width (default 640)")
    p.add_argument("--height", type=positive_int, default=480, help="frame height (default 480)")
    p.add_argument("--fps", type=positive_int, default=30, help="frames per simulated second (default 30)")
    p.add_argument("--seed", type=seed_arg, default=0, help="episode seed (default 0)")
    p.add_argument("--perturb", action="store_true", help="jitter the start, nudge a cube, drop a carried cube")
    p.add_argument("--perception", choices=("pose", "camera"), default="pose", help="perception mode")
    p.add_argument("--workers", type=positive_int, default=cores, help=f"render processes (default {cores})")
    add_quiet(p)
    p.set_defaults(func=cmd_render)

    p = sub.add_parser("evaluate", help="run physical episodes over start/goal pairs and report success")
    p.add_argument("--rules", help="a rule base from 'csql-sim train' (default: the BFS planner)")
    p.add_argument("--blocks", type=blocks_arg, default=3, help="number of blocks, 2..6 (default 3)")
    p.add_argument("--pairs", type=pairs_arg, default="all", help="'all' (default) or a sample size K")
    p.add_argument("--seeds", type=positive_int, default=1, help="episodes per pair (default 1)")
    p.add_argument("--perturb", action="store_true", help="jitter the start, nudge a cube, drop a carried cube")
    p.add_argument("--perception", choices=("pose", "camera"), default="pose", help="perception mode")
    p.add_argument("--workers", type=positive_int, default=cores, help=f"processes (default {cores})")
    p.add_argument("--json", help="also write the report as JSON to this file")
    add_quiet(p)
    p.set_defaults(func=cmd_evaluate)


__all__ = ["register"]
