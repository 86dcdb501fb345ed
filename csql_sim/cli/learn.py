"""Subcommands of learning: ``experiment``, ``train``, ``show``, ``prune`` and ``bench``."""

from __future__ import annotations

import argparse
import time

from csql_sim.cli.args import (
    add_quiet,
    blocks_arg,
    non_negative_int,
    positive_int,
    seed_arg,
    show_progress,
    threshold_arg,
    warn_workers,
)
from csql_sim.cli.core import read_task_for_rules
from csql_sim.errors import CsqlError


def _methods(text: str) -> list[str]:
    from csql_sim.learners import METHODS

    names = list(dict.fromkeys(m.strip().lower() for m in text.split(",") if m.strip()))  # once each, in order
    for m in names:
        if m not in METHODS:
            raise argparse.ArgumentTypeError(f"unknown method {m!r}; choose from {','.join(METHODS)}")
    if not names:
        raise argparse.ArgumentTypeError("no methods given")
    return names


# ------------------------------------------------------------------ experiment
def cmd_experiment(args: argparse.Namespace) -> int:
    from csql_sim.experiment import run_experiment, summary_lines, write_figure7
    from csql_sim.figure7_statements import evaluate, statement_lines
    from csql_sim.files import check_output_folder
    from csql_sim.workers import worker_count

    check_output_folder(args.out)
    warn_workers(args.workers)
    began = time.perf_counter()
    result = run_experiment(
        methods=args.methods, cycles=args.cycles, trials=args.trials, seed=args.seed,
        workers=args.workers, n=args.blocks, params=args.params, progress=show_progress(args),
    )
    wall = time.perf_counter() - began
    csv_path, png_path = write_figure7(args.out, result)
    for line in summary_lines(result):
        print(line)
    statements = evaluate(result)
    if statements:
        print(f"the paper's statements about Figure 7 ({sum(s.holds for s in statements)} of {len(statements)} hold):")
        for line in statement_lines(statements):
            print(f"  {line}")
    workers = worker_count(args.workers, len(args.methods) * args.cycles)
    print(f"wall time {wall:.1f} s with {workers} worker{'s' if workers > 1 else ''}")
    print(f"wrote {csv_path} and {png_path}")
    return 0


# ------------------------------------------------------------------ train
def cmd_train(args: argparse.Namespace) -> int:
    from csql_sim.files import check_output_file, write_or_keep
    from csql_sim.learners import count_q, train
    from csql_sim.rulebase import dumps

    check_output_file(args.out, "rule file")
    began = time.perf_counter()
    rb = train(args.method, args.trials, args.seed, args.blocks, args.params, progress=show_progress(args))
    wall = time.perf_counter() - began
    path = write_or_keep([(args.out, dumps(rb))])[0]
    r_count = sum(1 for c in rb.classifiers if c.kind == "R")
    print(
        f"{args.method}: {args.trials} trials, seed {args.seed}, {rb.meta['steps']} steps in {wall:.2f} s; "
        f"{r_count} R- and {count_q(rb)} Q-classifiers written to {path}"
    )
    return 0


# ------------------------------------------------------------------ show
def cmd_show(args: argparse.Namespace) -> int:
    from csql_sim.learners import figure6_table
    from csql_sim.rulebase import load

    rb = load(args.rules)
    if (args.start is None) != (args.goal is None):
        raise CsqlError("show needs both --start and --goal, or neither")
    start = goal = None
    if args.start is not None:
        start, goal = read_task_for_rules(args.start, args.goal, rb.blocks, args.rules)
    print(figure6_table(rb, start, goal))
    return 0


# ------------------------------------------------------------------ prune
def cmd_prune(args: argparse.Namespace) -> int:
    from csql_sim.files import check_output_file, write_or_keep
    from csql_sim.learners import count_q, prune
    from csql_sim.rulebase import dumps, load

    check_output_file(args.out, "rule file")
    rb = load(args.rules)
    pruned = prune(rb, args.threshold)
    path = write_or_keep([(args.out, dumps(pruned))])[0]
    print(f"Q-classifiers: {count_q(rb)} before, {count_q(pruned)} after pruning at {args.threshold:g}; wrote {path}")
    return 0


# ------------------------------------------------------------------ bench
def cmd_bench(args: argparse.Namespace) -> int:
    from csql_sim.learners.bench import bench

    r = bench(args.trials, args.seed, args.repeats)
    print(f"{r.trials} trials, best of {args.repeats}, same tasks and uniforms for both learners")
    print(f"  CS-QL (classifier system): {r.csql_steps} steps in {r.csql_seconds * 1000:.1f} ms, "
          f"{r.csql_steps / r.csql_seconds:,.0f} steps/s")
    print(f"  plain dict Q-learner:      {r.plain_steps} steps in {r.plain_seconds * 1000:.1f} ms, "
          f"{r.plain_steps / r.plain_seconds:,.0f} steps/s")
    print(f"  ratio CS-QL / plain steps per second: {r.ratio:.2f}x")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``experiment``, ``train``, ``show``, ``prune`` and ``bench`` to the subparsers."""
    from csql_sim.learners import METHODS

    p = sub.add_parser("experiment", help="Figure 7: test-task curves of the learners over cycles")
    p.add_argument("--methods", type=_methods, default=list(METHODS), help=f"comma list (default {','.join(METHODS)})")
    p.add_argument("--cycles", type=positive_int, default=50, help="cycles per method (default 50)")
    p.add_argument("--trials", type=non_negative_int, default=2500, help="trials per cycle (default 2500)")
    p.add_argument("--seed", type=seed_arg, default=0, help="root seed (default 0)")
    p.add_argument("--workers", type=positive_int, default=None, help="processes (default: all cores)")
    p.add_argument("--blocks", type=blocks_arg, default=3, help="number of blocks (default 3)")
    p.add_argument("--params", help="YAML parameter overrides (flat, or keyed by method)")
    p.add_argument("--out", required=True, help="folder for figure7.csv and figure7.png")
    add_quiet(p)
    p.set_defaults(func=cmd_experiment)

    p = sub.add_parser("train", help="train one agent and save its classifier list")
    p.add_argument("--method", choices=METHODS, default="cs-ql", help="learner (default cs-ql)")
    p.add_argument("--trials", type=non_negative_int, default=2500, help="training trials (default 2500)")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed (default 0)")
    p.add_argument("--blocks", type=blocks_arg, default=3, help="number of blocks (default 3)")
    p.add_argument("--params", help="YAML parameter overrides")
    p.add_argument("--out", required=True, help="rule file to write (YAML)")
    add_quiet(p)
    p.set_defaults(func=cmd_train)

    p = sub.add_parser("show", help="print Q-classifiers in Figure 6's table form")
    p.add_argument("rules", help="a rule file from 'csql-sim train'")
    p.add_argument("--start", help="with --goal: show just the greedy path's classifiers")
    p.add_argument("--goal", help="goal configuration, e.g. BAC")
    p.set_defaults(func=cmd_show)

    p = sub.add_parser("prune", help="remove Q-classifiers below a strength threshold")
    p.add_argument("rules", help="a rule file from 'csql-sim train'")
    p.add_argument("--threshold", type=threshold_arg, default=0.1, help="strength threshold in [0, 1] (default 0.1)")
    p.add_argument("--out", required=True, help="rule file to write")
    p.set_defaults(func=cmd_prune)

    p = sub.add_parser("bench", help="time CS-QL against a plain dict-based Q-learner on the same trials")
    p.add_argument("--trials", type=non_negative_int, default=2500, help="training trials (default 2500)")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed (default 0)")
    p.add_argument("--repeats", type=positive_int, default=15, help="best of this many runs (default 15)")
    p.set_defaults(func=cmd_bench)


__all__ = ["register"]
