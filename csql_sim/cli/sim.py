"""Subcommands of the physical world: ``render`` and ``evaluate``."""

from __future__ import annotations

import argparse
import json
import sys
from typing import TYPE_CHECKING

from csql_sim.cli.args import (
    RULES_BUILTIN_HELP,
    add_backend_arguments,
    add_json,
    add_planner,
    add_quiet,
    add_video_options,
    add_workers,
    backend_from_args,
    blocks_arg,
    blocks_help,
    command_parser,
    path_arg,
    positive_int,
    rules_arg,
    seed_arg,
    show_progress,
    video_options,
    warn_workers,
)
from csql_sim.cli.output import default_path, emit
from csql_sim.cli.plan import read_task, read_task_for_rules, relational_blocks
from csql_sim.cli.plan_view import select_policy
from csql_sim.cli.sim_options import (
    DISCOVERY_BLOCKS,
    DISCOVERY_TRANSITIONS,
    LARGE_DEFAULT_PAIRS,
    NO_NOISE,
    add_camera_noise,
    check_evaluate_options,
    check_render_options,
)
from csql_sim.core.state.world import MAX_BLOCKS, MIN_BLOCKS, State
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import Outputs
from csql_sim.jobs.baselines import NAMED_POLICIES
from csql_sim.sim.world import MAX_ARM_BLOCKS

DEFAULT_VIDEO = "video.mp4"

if TYPE_CHECKING:
    from csql_sim.jobs.evaluate import EvalReport
    from csql_sim.sim.control import EpisodeResult


def arm_blocks_arg(text: str) -> int:
    """Argparse type for the arm's ``--blocks``: 2..30 cubes; more are refused with the reason."""
    try:
        n = int(text.strip())
    except ValueError:
        n = 0
    if n < MIN_BLOCKS:
        raise argparse.ArgumentTypeError(f"must be an integer {MIN_BLOCKS}..{MAX_ARM_BLOCKS}, got {text!r}")
    if n > MAX_ARM_BLOCKS:
        raise argparse.ArgumentTypeError(
            f"the arm takes at most {MAX_ARM_BLOCKS} cubes (the table's ring has {MAX_ARM_BLOCKS} places within the "
            f"Panda's reach), got {n}")
    return n


def read_arm_task(start: str, goal: str | None, rules: str | None) -> tuple[State, State]:
    """The task of ``render``: as ``plan`` reads it up to six blocks, else a task of 7..30 cubes.

    The start decides which, as for ``plan`` (:func:`csql_sim.cli.plan.relational_blocks`):
    a configuration of more than six blocks or a large state message is read with the
    cubes' names (A..Z, AA, ...) or as a large message (:func:`csql_sim.cli.plan.read_task`),
    so an error in the goal names the goal; more than 30 cubes, or a tower taller than the
    arm's limit, are refused with one line.
    """
    from csql_sim.sim.world import check_arm_blocks, check_tower_heights

    if relational_blocks(argparse.Namespace(blocks=None, start=start, pairs=None)) is None:
        s, g = read_task_for_rules(start, goal, None, rules)
    else:
        s, g = read_task(start, goal, None)
        check_arm_blocks(s.n)
    check_tower_heights(s, g)
    return s, g


def arm_policy(args: argparse.Namespace, n: int) -> object:
    """The policy of ``--planner`` and ``--rules`` for n cubes (past six blocks: lifted only)."""
    return select_policy(args, n)


def pairs_arg(text: str) -> str | int:
    """Argparse type for --pairs: ``all`` or a positive integer."""
    if text.strip().lower() == "all":
        return "all"
    return positive_int(text)


def episode_text(result: EpisodeResult, n: int) -> list[str]:
    """The legend of the ``n`` cubes and the episode (:func:`csql_sim.sim.control.report.episode_lines`)."""
    from csql_sim.sim.control import episode_lines
    from csql_sim.sim.world import legend_line

    return [legend_line(n), *episode_lines(result)]


def print_episode(result: EpisodeResult, n: int) -> None:
    """Print :func:`episode_text`."""
    print("\n".join(episode_text(result, n)))


def episode_doc(result: EpisodeResult) -> dict:
    """An episode for a ``--json`` report: the task, the verdict from perception and each action run."""
    return {"start": result.start, "goal": result.goal, "seed": result.seed, "success": result.success,
            "reason": result.reason, "length": result.length, "optimal_length": result.optimal_length,
            "sim_seconds": round(result.sim_seconds, 3),
            "steps": [{"action": s.action, "predicted": s.predicted, "perceived": s.perceived} for s in result.steps]}


def declare_render(args: argparse.Namespace, outputs: Outputs) -> None:
    """The video (default ``video.mp4``) and, for an episode, its provenance sidecar ``<video>.json``."""
    from csql_sim.jobs.render import sidecar_path

    default = default_path(args, "out", DEFAULT_VIDEO)
    video_options(args).check(args.out)
    sidecar = sidecar_path(args.out)
    outputs.file(args.out, "video file", "video", default=default)
    outputs.file(sidecar, "video provenance", "json", default=default)
    outputs.input(args.rules, "rule file")
    outputs.input(args.problem, "PDDL problem")


def declare_evaluate(args: argparse.Namespace, outputs: Outputs) -> None:
    """``--plot FILE.png`` (with ``--json FILE``, added by the caller); ``--rules`` is read."""
    if args.plot is not None:
        if not args.plot.lower().endswith(".png"):
            raise CsqlError(f"--plot must name a .png file, got {args.plot!r}")
        outputs.file(args.plot, "plot", "png", option="--plot")
    outputs.input(args.rules, "rule file")
    outputs.input(args.domain, "domain file")
    outputs.input_folder(getattr(args, "problems", None), "PDDL problem")
    outputs.input_folder(getattr(args, "plans", None), "plan file", "*")


def cmd_render(args: argparse.Namespace) -> int:
    from csql_sim.infra.provenance import rules_source
    from csql_sim.jobs.render import render_episode, sidecar_path
    from csql_sim.sim.perception import CameraNoise
    from csql_sim.sim.video import video_frame_count

    check_render_options(args)
    if args.discovery:
        return render_discovery(args)
    if args.problem is not None:
        return render_problem(args)
    if not args.start:
        raise CsqlError("render needs --start and --goal, or --problem")
    video_options(args).check(args.out)
    warn_workers(args)
    start, goal = read_arm_task(args.start, args.goal, args.rules)
    policy = arm_policy(args, start.n)
    result, path = render_episode(start, goal, args.out, policy, seed=args.seed, width=args.width,
                                  height=args.height, fps=args.fps, speed=args.speed, workers=args.workers,
                                  perturb=args.perturb, perception=args.perception, progress=show_progress(args),
                                  provenance_extra={"rules": rules_source(args.rules),
                                                    **({"planner": args.planner} if args.planner else {})},
                                  camera_noise=CameraNoise(*args.camera_noise), renderer=args.renderer)
    frames = video_frame_count(result.recording, args.fps) if result.recording else 0
    doc = {**episode_doc(result), "video": str(path), "frames": frames, "sidecar": str(sidecar_path(path))}
    emit(args, doc, lambda: [*episode_text(result, start.n), f"wrote {path} ({frames} frames at {args.fps} fps, "
                             f"{args.width}x{args.height}; provenance in {sidecar_path(path)})"])
    return 0 if result.success else 1


def render_problem(args: argparse.Namespace) -> int:
    """``render --problem FILE``: ``execute``'s run of a PDDL problem with a video, in the problem's names.

    The plan comes from ``--rules`` or ``--planner`` (default: BFS up to six blocks, GN1 past six).
    """
    from csql_sim.jobs.execute import execute_problem

    if args.start or args.goal:
        raise CsqlError("render --problem FILE takes its start and goal from the file; give no --start or --goal")
    if args.camera_noise != NO_NOISE:
        raise CsqlError("--camera-noise does not apply to render --problem")
    warn_workers(args)
    planner = None if args.rules is not None else args.planner
    if args.rules is None and planner is None:
        from csql_sim.core.files.pddl_import import MAX_PLANNED_BLOCKS, read_problem

        planner = "bfs" if read_problem(args.problem, max_blocks=MAX_PLANNED_BLOCKS).n <= MAX_BLOCKS else "gn1"
    result = execute_problem(args.problem, rules=args.rules, planner=planner, seed=args.seed,
                             perception=args.perception, perturb=args.perturb, video=args.out,
                             progress=show_progress(args), video_options=video_options(args))
    emit(args, result.to_dict(), result.lines)
    print(f"wrote {result.video} (provenance in {result.video}.json)", file=sys.stderr)
    return 0 if result.reached else 1


def _rate(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number in 0..1, got {text!r}") from None
    if not 0.0 <= value <= 1.0:  # also refuses nan
        raise argparse.ArgumentTypeError(f"must be a number in 0..1, got {text}")
    return value


def evaluate_status(report: EvalReport, min_success: float | None) -> int:
    """0 when the run succeeded: every episode, or a success rate of at least ``min_success``."""
    if min_success is None:
        return 0 if report.episodes and report.successes == report.episodes else 1
    return 0 if report.episodes and report.success_rate >= min_success else 1


def render_discovery(args: argparse.Namespace) -> int:
    """``render --discovery``: a short discovery episode, failed attempts captioned as such."""
    from csql_sim.core.state.message import parse_action_message
    from csql_sim.infra.files import write_atomic
    from csql_sim.infra.provenance import provenance
    from csql_sim.jobs.discover import record_discovery
    from csql_sim.jobs.job_memory import check_discovery
    from csql_sim.jobs.render import sidecar_path, sidecar_record
    from csql_sim.sim.video import video_frame_count, write_video
    from csql_sim.sim.world import cube_legend, legend_line

    if args.start or args.goal or args.rules or args.problem:
        raise CsqlError("render --discovery takes no --start, --goal, --rules or --problem")
    out = video_options(args).check(args.out)
    args.blocks = args.blocks or DISCOVERY_BLOCKS
    args.transitions = args.transitions or DISCOVERY_TRANSITIONS
    check_discovery(args.transitions, args.blocks, args.fps, args.width, args.height, out.suffix.lower() == ".gif")
    warn_workers(args)
    result, recording = record_discovery(args.blocks, args.seed, args.transitions, args.fps / args.speed,
                                         args.perception, args.perturb)

    lines = [legend_line(args.blocks)]
    for t in result.log:
        name = parse_action_message(t.action, args.blocks).name()
        lines.append(f"  {t.before}  {name:<14} {'ok' if t.ok else 'FAILED: ' + t.reason}")
    path = write_video(recording, args.out, args.width, args.height, args.fps, args.workers,
                       progress=show_progress(args), renderer=args.renderer)
    frames = video_frame_count(recording, args.fps)
    record = provenance(command="render --discovery", blocks=args.blocks, seed=args.seed,
                        transitions=args.transitions, perception=args.perception, perturb=args.perturb,
                        width=args.width, height=args.height, fps=args.fps)
    video = {"file": path.name, "frames": frames, "attempts": result.transitions, "failed": result.failed,
             "legend": cube_legend(args.blocks)}
    sidecar = write_atomic(sidecar_path(path), json.dumps(sidecar_record(record, video), indent=1) + "\n")
    emit(args, {**video, "video": str(path), "sidecar": str(sidecar)},
         [*lines, f"{result.transitions} attempts, {result.failed} failed; wrote {path} ({frames} frames) and "
                  f"{sidecar}"])
    return 0


def cmd_evaluate(args: argparse.Namespace) -> int:
    from csql_sim.infra.provenance import provenance
    from csql_sim.jobs.evaluate import evaluate

    check_evaluate_options(args)
    if args.problems is not None or args.plans is not None or args.domain is not None:
        return _evaluate_problems(args)
    warn_workers(args)
    report = evaluate(n=args.blocks, pairs=args.pairs, seeds=args.seeds, perturb=args.perturb,
                      rules=args.rules, perception=args.perception, progress=show_progress(args),
                      seed=args.seed, camera_noise=args.camera_noise, backend=backend_from_args(args),
                      planner=_named_planner(args))
    status = evaluate_status(report, args.min_success)
    emit(args, {**report.to_dict(), "min_success": args.min_success, "status": status,
                "provenance": provenance(command="evaluate", **report.config, min_success=args.min_success)},
         report.text)
    if args.plot is not None:
        from csql_sim.jobs.plots import write_evaluation_png

        print(f"wrote {write_evaluation_png(report, args.plot)}", file=sys.stderr)
    return status


def _named_planner(args: argparse.Namespace) -> str | None:
    """``evaluate --planner``: the named baseline to run (``gn1``, ``gn2``), or None for ``--rules`` / BFS."""
    planner = args.planner or ("rules" if args.rules else "bfs")
    if planner == "rules" and not args.rules:
        raise CsqlError("--planner rules needs --rules FILE")
    if planner != "rules" and args.rules:
        raise CsqlError(f"--planner {planner} does not read --rules {args.rules!r}; give one of them")
    return planner if planner in NAMED_POLICIES else None


def _evaluate_problems(args: argparse.Namespace) -> int:
    """``evaluate --problems DIR``: every problem of a folder on the arm, one after another."""
    from csql_sim.jobs.execute_batch import evaluate_problems, problems_lines, problems_report

    if args.problems is None:
        raise CsqlError("--plans and --domain go with --problems DIR")
    if args.plot is not None:
        raise CsqlError("--plot draws pairs; it does not apply to --problems")
    if args.plans is not None and args.planner is not None:
        raise CsqlError(f"--plans DIR runs the plans it holds; --planner {args.planner} does not apply")
    planner = None  # a plan folder or a rule base, else a named baseline (gn1, gn2) or BFS
    if args.plans is None:
        planner = _named_planner(args) or (None if args.rules else "bfs")  # --planner rules needs --rules
    runs = evaluate_problems(args.problems, plans=args.plans, rules=args.rules, planner=planner,
                             domain=args.domain, seed=args.seed, perception=args.perception, perturb=args.perturb,
                             progress=show_progress(args))
    params = {"problems": args.problems, "plans": args.plans, "rules": args.rules, "planner": planner,
              "domain": args.domain, "seed": args.seed, "perception": args.perception, "perturb": args.perturb}
    emit(args, problems_report(runs, params), problems_lines(runs))
    rate = sum(r.reached for r in runs) / len(runs)
    return 0 if rate >= (args.min_success if args.min_success is not None else 1.0) else 1


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``render`` and ``evaluate`` to the subparsers."""
    _register_render(sub)
    _register_evaluate(sub)


def _register_render(sub: argparse._SubParsersAction) -> None:
    p = command_parser(sub, "render", "execute a plan on the simulated Panda and write a captioned video",
                       "csql-sim render --start CBA --goal BAC --out task.mp4")
    p.add_argument("--start", help="start configuration, e.g. CBA (A on B on C); '+X' holds X")
    p.add_argument("--goal", help="goal configuration, e.g. BAC")
    p.add_argument("--problem", type=path_arg,
                   help="a blocks-world PDDL problem instead of --start and --goal (as 'execute' runs it: "
                   "the plan of --rules or --planner, default bfs up to six blocks, gn1 past six)")
    p.add_argument("--rules", type=rules_arg,
                   help="a rule base from 'csql-sim train', or lifted rules (any n; default: the BFS planner)"
                        + RULES_BUILTIN_HELP)
    add_planner(p, f"up to {MAX_BLOCKS} blocks; gn1, gn2 and lifted rules: any n")
    p.add_argument("--out", type=path_arg, default=None,
                   help=f"output .mp4 or .gif (default {DEFAULT_VIDEO}; an existing one is kept unless --overwrite)")
    p.add_argument("--seed", type=seed_arg, default=0, help="episode seed (default 0)")
    p.add_argument("--perturb", action="store_true", help="jitter the start, nudge a cube, drop a carried cube")
    p.add_argument("--perception", choices=("pose", "camera"), default="pose", help="perception mode (default pose)")
    add_camera_noise(p)
    add_video_options(p)
    add_quiet(p)
    p.add_argument("--discovery", action="store_true",
                   help="show a discovery episode instead: random attempts, failed ones captioned as such")
    p.add_argument("--transitions", type=positive_int, default=None,
                   help=f"attempts in --discovery (default {DISCOVERY_TRANSITIONS})")
    p.add_argument("--blocks", type=blocks_arg, default=None,
                   help=blocks_help(2, MAX_BLOCKS, DISCOVERY_BLOCKS, "; with --discovery only: a task's blocks "
                                    "come from --start"))
    add_json(p)
    p.set_defaults(func=cmd_render, declare=declare_render)


def _register_evaluate(sub: argparse._SubParsersAction) -> None:
    p = command_parser(sub, "evaluate", "run physical episodes over start/goal pairs and report success",
                       "csql-sim evaluate --blocks 3 --rules rules.yaml")
    p.add_argument("--rules", type=rules_arg,
                   help="a rule base from 'csql-sim train', or lifted rules (any n; default: the BFS planner)"
                        + RULES_BUILTIN_HELP)
    add_planner(p, f"up to {MAX_BLOCKS} blocks; gn1, gn2 and lifted rules: any n")
    p.add_argument("--blocks", type=arm_blocks_arg, default=None,
                   help=blocks_help(2, MAX_ARM_BLOCKS, 3, f"; past {MAX_BLOCKS} the states are relational and the "
                                    f"policy lifted: --planner gn1|gn2, or lifted --rules"))
    p.add_argument("--pairs", type=pairs_arg, default=None,
                   help=f"'all' (the default up to {MAX_BLOCKS} blocks) or a sample size K (past {MAX_BLOCKS} "
                        f"blocks drawn uniformly by counting; default {LARGE_DEFAULT_PAIRS}, --seed 0)")
    p.add_argument("--seed", type=seed_arg, default=None,
                   help="seed of the sample of --pairs K, or of each episode with --problems (default 0)")
    p.add_argument("--seeds", type=positive_int, default=None, help="episodes per pair (default 1)")
    p.add_argument("--perturb", action="store_true", help="jitter the start, nudge a cube, drop a carried cube")
    p.add_argument("--perception", choices=("pose", "camera"), default="pose", help="perception mode (default pose)")
    add_camera_noise(p)
    p.add_argument("--min-success", type=_rate, metavar="RATE",
                   help="exit 0 when the success rate is at least RATE (default: every episode must succeed)")
    p.add_argument("--plot", metavar="FILE.png", type=path_arg,
                   help="draw outcomes, plan lengths and perturbations to a PNG")
    p.add_argument("--problems", type=path_arg, metavar="DIR",
                   help="run every PDDL problem of DIR instead of pairs (with --plans DIR, --rules, "
                        "--planner gn1|gn2 or BFS)")
    p.add_argument("--plans", type=path_arg, metavar="DIR",
                   help="with --problems: the plan files (<problem>.plan, .soln or .pddl.soln)")
    p.add_argument("--domain", type=path_arg, help="with --problems: their PDDL domain file (optional)")
    add_workers(p, "processes, or CPUs of a local Ray instance")
    add_backend_arguments(p)
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_evaluate, declare=declare_evaluate)


__all__ = ["register"]
