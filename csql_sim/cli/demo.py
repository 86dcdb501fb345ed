"""The main job, ``csql-sim demo``: learn, prune, show Figure 6, execute on the arm, video.

The README's first quick-start command runs it with its defaults.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from csql_sim.cli.args import (
    add_json,
    add_quiet,
    add_renderer_argument,
    add_workers,
    blocks_arg,
    blocks_help,
    command_parser,
    path_arg,
    positive_int,
    seed_arg,
    show_progress,
    threshold_arg,
    warn_workers,
)
from csql_sim.cli.output import default_path, emit, wants_json
from csql_sim.infra.outputs import Outputs

DEFAULT_OUT = "out"
VIDEO = "test_task.mp4"


def declare_demo(args: argparse.Namespace, outputs: Outputs) -> None:
    """The folder (default ``out/``) and the four files the demo writes in it.

    In the default folder no existing file is replaced unless ``--overwrite`` is given; in a
    folder the user named, existing files are replaced when they are csql-sim's own.
    """
    from csql_sim.jobs.render import sidecar_path
    from csql_sim.sim.video import check_video_options

    default = default_path(args, "out", DEFAULT_OUT)
    out = outputs.folder(args.out, "output folder", default=default)
    video = out / VIDEO
    check_video_options(video, args.width, args.height, args.fps)
    outputs.file(out / "rules.yaml", "rule file", "rules", default=default)
    outputs.file(out / "pruned.yaml", "pruned rule file", "rules", default=default)
    outputs.file(video, "video file", "video", default=default)
    outputs.file(sidecar_path(video), "video provenance", "json", default=default)


def cmd_demo(args: argparse.Namespace) -> int:
    from csql_sim.cli.sim import episode_doc, episode_text
    from csql_sim.core.files.rulebase import dumps
    from csql_sim.core.model.task import test_task
    from csql_sim.core.policies.policy import QPolicy
    from csql_sim.core.policies.rollout import check_all_pairs
    from csql_sim.infra.files import write_or_keep
    from csql_sim.infra.provenance import rules_source
    from csql_sim.jobs.render import render_episode
    from csql_sim.learners.generalize import count_q, figure6_table, prune
    from csql_sim.learners.paper import default_trials
    from csql_sim.learners.training import train
    from csql_sim.sim.video import resolve_renderer

    out = Path(args.out)
    video = out / VIDEO
    warn_workers(args)
    resolve_renderer(args.renderer)  # fail before training if --renderer egl cannot load
    if args.trials is None:
        args.trials = default_trials(args.blocks)
    task = test_task(args.blocks)
    start, goal = task.start, task.goal
    progress = show_progress(args)

    say = _narrator(args)
    say(f"[1/4] training CS-QL: {args.blocks} blocks, {args.trials} trials, seed {args.seed}")
    learned = train("cs-ql", trials=args.trials, seed=args.seed, n=args.blocks, progress=progress)
    pruned = prune(learned, args.threshold)
    write_or_keep([(out / "rules.yaml", dumps(learned)), (out / "pruned.yaml", dumps(pruned))])
    before, after = count_q(learned), count_q(pruned)
    policy = QPolicy.from_rulebase(pruned)
    results = check_all_pairs(policy, pruned.blocks, progress=progress)
    optimal = sum(r.optimal for r in results)
    say(f"[2/4] pruning at strength {args.threshold}: {before} -> {after} Q-classifiers; "
          f"the pruned rules plan {optimal}/{len(results)} start/goal pairs optimally "
          f"(rule files: {out / 'rules.yaml'}, {out / 'pruned.yaml'})")

    say(f"[3/4] the test task's Q-classifiers ({start.notation()} -> {goal.notation()}), as in Figure 6:")
    say(figure6_table(pruned, start, goal))

    say(f"[4/4] executing the learned plan on the simulated Panda and rendering {video}")
    result, path = render_episode(start, goal, video, policy, seed=args.seed, width=args.width,
                                  height=args.height, fps=args.fps, workers=args.workers, progress=progress,
                                  provenance_extra={"rules": rules_source(out / "pruned.yaml"), "trials": args.trials,
                                                    "threshold": args.threshold},
                                  renderer=args.renderer)
    verdict = (f"goal reached physically: yes (the perceived state is {goal.notation()} and the scene has settled)"
               if result.success else f"goal reached physically: NO ({result.reason})")
    doc = {"blocks": args.blocks, "trials": args.trials, "seed": args.seed, "threshold": args.threshold,
           "q_before": before, "q_after": after, "optimal_pairs": optimal, "pairs": len(results),
           "rules": str(out / "rules.yaml"), "pruned": str(out / "pruned.yaml"), "video": str(path),
           "episode": episode_doc(result)}
    emit(args, doc, lambda: [*episode_text(result, start.n), f"video: {path}", verdict])
    return 0 if result.success else 1


def _narrator(args: argparse.Namespace):  # noqa: ANN202 - a function taking one line
    """How the demo tells its steps: on stdout, or with ``--json`` on stderr (nothing with ``--quiet``)."""
    if not wants_json(args):
        return print
    if args.quiet:
        return lambda text: None
    return lambda text: print(text, file=sys.stderr)


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``demo`` to the subparsers."""
    p = command_parser(sub, "demo", "train CS-QL, prune, show Figure 6, run the test task on the arm, write a video",
                       "csql-sim demo --out out")
    p.add_argument("--out", type=path_arg, default=None,
                   help=f"output folder (default {DEFAULT_OUT}/; its existing files are kept unless --overwrite)")
    p.add_argument("--trials", type=positive_int, default=None,
                   help="training trials (default by n, as 'train': 2500 for n <= 3, 20000 for n = 4 and 5)")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed for training and the episode (default 0)")
    p.add_argument("--threshold", type=threshold_arg, default=0.1,
                   help="pruning strength threshold in [0, 1] (default 0.1)")
    p.add_argument("--width", type=positive_int, default=640, help="frame width (default 640)")
    p.add_argument("--height", type=positive_int, default=480, help="frame height (default 480)")
    p.add_argument("--fps", type=positive_int, default=30, help="frames per simulated second (default 30)")
    p.add_argument("--blocks", type=blocks_arg, default=3,
                   help=blocks_help(2, 6, 3, ": the paper's test task CBA -> BAC; see 'experiment'"))
    add_workers(p, "rendering processes")
    add_quiet(p)
    add_renderer_argument(p)
    add_json(p)
    p.set_defaults(func=cmd_demo, declare=declare_demo)
