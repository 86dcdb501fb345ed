"""Subcommands of learning: ``experiment``, ``train``, ``show``, ``prune``, ``scaling`` and ``bench``."""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import fields

from csql_sim.cli.args import (
    add_backend_arguments,
    add_domain_rules,
    add_json,
    add_overwrite,
    add_quiet,
    add_workers,
    backend_from_args,
    blocks_arg,
    blocks_help,
    command_parser,
    non_negative_int,
    path_arg,
    positive_int,
    seed_arg,
    show_progress,
    warn_workers,
)
from csql_sim.cli.learn_options import modes_arg, phase_lines, replay_ratio_arg, train_params
from csql_sim.cli.output import emit, json_text, with_format
from csql_sim.cli.train_shards import add_size_arguments, train_blocks_arg
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import Outputs

FIGURE7_FILES = ("figure7.csv", "figure7.json", "figure7.png")
SCALING_FILES = ("scaling.csv", "scaling.json", "scaling.png")


def declare_folder(args: argparse.Namespace, outputs: Outputs, names: tuple[str, str, str]) -> None:
    """An output folder with a CSV, its provenance JSON (which vouches for both others) and a PNG."""
    out = outputs.folder(args.out, "output folder")
    csv_name, json_name, png_name = names
    outputs.file(out / csv_name, "CSV table", "csv")
    outputs.file(out / json_name, "provenance", "json")
    outputs.file(out / png_name, "figure", "png")
    outputs.input(getattr(args, "params", None), "parameter file")


def declare_rule_file(args: argparse.Namespace, outputs: Outputs) -> None:
    """``train`` and ``prune``: one rule file; the rule files and parameters they read are inputs."""
    outputs.file(args.out, "rule file", "rules")
    outputs.input(getattr(args, "rules", None), "rule file")
    outputs.input(getattr(args, "domain_rules", None), "domain rule file")
    outputs.input(getattr(args, "params", None), "parameter file")


def _methods(text: str) -> list[str]:
    from csql_sim.learners.training import METHODS

    names = list(dict.fromkeys(m.strip().lower() for m in text.split(",") if m.strip()))  # once each, in order
    for m in names:
        if m not in METHODS:
            raise argparse.ArgumentTypeError(f"unknown method {m!r}; choose from {','.join(METHODS)}")
    if not names:
        raise argparse.ArgumentTypeError("no methods given")
    return names


# ------------------------------------------------------------------ experiment
def cmd_experiment(args: argparse.Namespace) -> int:
    from csql_sim.jobs.experiment import run_experiment, summary_lines, write_figure7
    from csql_sim.jobs.figure7_statements import evaluate, statement_lines
    from csql_sim.learners.paper import default_trials

    warn_workers(args)
    began = time.perf_counter()
    trials = args.trials if args.trials is not None else default_trials(args.blocks)
    result = run_experiment(
        methods=args.methods, cycles=args.cycles, trials=trials, seed=args.seed,
        n=args.blocks, params=args.params, progress=show_progress(args), backend=backend_from_args(args),
    )
    wall = time.perf_counter() - began
    csv_path, sidecar, png_path = write_figure7(args.out, result)
    statements = evaluate(result) if args.blocks == 3 else []  # the paper's statements are about n = 3
    workers = result.workers
    doc = {**result.to_dict(), "wall_seconds": round(wall, 3),
           "statements": [{"name": st.name, "text": st.text, "holds": st.holds, "measured": st.measured}
                          for st in statements],
           "files": {"csv": str(csv_path), "provenance": str(sidecar), "png": str(png_path)}}

    def text() -> list[str]:
        lines = summary_lines(result)
        if statements:
            held = sum(st.holds for st in statements)
            lines.append(f"the paper's statements about Figure 7 ({held} of {len(statements)} hold):")
            lines.extend(f"  {line}" for line in statement_lines(statements))
        where = f"with {workers} worker{'s' if workers > 1 else ''}"
        if args.backend == "ray":
            where = f"on Ray ({args.address or 'a local instance'})"
        return [*lines, f"wall time {wall:.1f} s {where}",
                f"wrote {csv_path}, {sidecar} (provenance) and {png_path}"]

    emit(args, doc, text)
    return 0


# ------------------------------------------------------------------ train
def cmd_train(args: argparse.Namespace) -> int:
    """``train``: the estimate first; then one engine and one rule file, or shards into a directory."""
    from csql_sim.cli import train_shards
    from csql_sim.infra.files import write_or_keep
    from csql_sim.learners.training import train_learner

    train_shards.settle(args)
    if args.params is not None and not args.resume:  # a bad parameter file: refused by --dry-run too
        from csql_sim.learners.paper import resolve_params

        resolve_params(args.method, args.params, args.blocks)
    out = None  # every refusal of the run comes before the estimate, so that --dry-run refuses it too
    if train_shards.sharded(args):
        out = train_shards.check_directory(args)
    elif args.backend != "processes" or args.address is not None:
        raise CsqlError("--backend ray trains shards of goals: give --shards K (one engine runs here)")
    status = train_shards.check_estimate(args)
    if status is not None:  # --dry-run
        return status
    if train_shards.sharded(args):
        return train_shards.run(args, out)

    domain = None
    if args.domain_rules:
        from csql_sim.core.files.rulebase import load_r_classifiers

        domain = load_r_classifiers(args.domain_rules, args.blocks).classifiers
    began = time.perf_counter()
    learner, meta = train_learner(args.method, args.trials, args.seed, args.blocks, train_params(args),
                                  progress=show_progress(args), engine=args.engine, domain=domain)
    if args.domain_rules:
        meta["domain"] = str(args.domain_rules)
    trained = time.perf_counter()
    if args.params:
        meta["provenance"]["parameters"]["params_file"] = args.params
    path = write_or_keep([(args.out, learner.file_bytes(args.out, meta))])[0]
    r_count, q_count = learner.counts()
    written = time.perf_counter() - trained
    doc = {"method": args.method, "engine": learner.engine, "blocks": args.blocks, "trials": meta["trials"],
           "seed": args.seed, "steps": meta["steps"], "training_seconds": round(trained - began, 3),
           "r_classifiers": r_count, "q_classifiers": q_count, "out": str(path), "phases": meta["phases"]}
    emit(args, doc, lambda: [
        f"{args.method} ({learner.engine} engine), {args.blocks} blocks: {meta['trials']} trials, seed {args.seed}, "
        f"{meta['steps']} steps in {trained - began:.2f} s; {r_count} R- and {q_count} Q-classifiers written to "
        f"{path} in {written:.2f} s", *(f"  {line}" for line in phase_lines(meta["phases"]))])
    return 0


def cmd_bench(args: argparse.Namespace) -> int:
    from csql_sim.infra.provenance import provenance
    from csql_sim.jobs.bench import bench

    r = bench(args.trials, args.seed, args.repeats)
    engines = {"reference": r.reference, "fast": r.fast, "plain": r.plain, "lt_reference": r.lt_reference,
               "lt_fast": r.lt_fast}
    doc = {"trials": r.trials, "repeats": args.repeats,
           **{k: {"steps": e.steps, "seconds": e.seconds, "steps_per_second": e.rate} for k, e in engines.items()},
           "identical": r.identical, "ratio": r.ratio, "fast_ratio": r.fast_ratio,
           "lt_identical": r.lt_identical, "lt_ratio": r.lt_ratio,
           "provenance": provenance(trials=args.trials, seed=args.seed, repeats=args.repeats)}

    def text() -> list[str]:
        lines = [f"{r.trials} trials (n = 3), seed {args.seed}, best of {args.repeats} in CPU time; "
                 "same tasks and uniforms for every learner"]
        for label, e in (("CS-QL reference engine", r.reference), ("CS-QL fast engine", r.fast),
                         ("plain dict Q-learner", r.plain), ("LT-QL reference engine", r.lt_reference),
                         ("LT-QL fast engine", r.lt_fast)):
            lines.append(f"  {label + ':':<24} {e.steps} steps in {e.seconds * 1000:8.1f} ms, {e.rate:>12,.0f} steps/s")
        return [*lines,
                f"  CS-QL's two engines: identical trajectories (same rule file): {'yes' if r.identical else 'NO'}",
                f"  LT-QL's two engines: identical trajectories (same rule file): {'yes' if r.lt_identical else 'NO'}",
                f"  ratio CS-QL reference / plain steps per second: {r.ratio:.2f}x",
                f"  ratio CS-QL fast / plain steps per second:      {r.fast_ratio:.1f}x",
                f"  ratio LT-QL fast / reference steps per second:  {r.lt_ratio:.1f}x"]

    emit(args, doc, text)
    return 0 if r.identical and r.lt_identical else 1


# ------------------------------------------------------------------ scaling
def cmd_scaling(args: argparse.Namespace) -> int:
    from csql_sim.infra.provenance import plain, provenance
    from csql_sim.jobs.scaling import VERSION, run_scaling, write_outputs

    rows = run_scaling(args.blocks, args.methods, args.seed, args.max_trials, progress=show_progress(args),
                       backend=backend_from_args(args), modes=args.modes)
    csv_path, sidecar, png_path = (os.path.join(args.out, name) for name in SCALING_FILES)
    record = provenance(blocks=args.blocks, methods=args.methods, seed=args.seed, max_trials=args.max_trials)
    doc = with_format({"rows": plain(rows), "files": {"csv": csv_path, "png": png_path}, "provenance": record},
                      "csql-sim scaling report", VERSION)
    write_outputs(args.out, rows, args.max_trials, sidecar=json_text(doc))

    def text() -> list[str]:
        lines = []
        for r in rows:
            when = f"all optimal after {r.trials} trials" if r.trials is not None else (
                f"cap {args.max_trials} reached: {r.optimal_pairs} of {r.pairs} pairs optimal")
            lines.append(f"{r.method:<6} {r.mode:<6} n={r.blocks}: {when}; {r.steps} steps, {r.wall_seconds:.1f} s, "
                         f"peak RSS {r.peak_rss_mb:.0f} MB, population {r.population}")
        return [*lines, f"wrote {csv_path}, {sidecar} (provenance) and {png_path}"]

    emit(args, doc, text)
    return 0


# ------------------------------------------------------------------ params
def cmd_params(args: argparse.Namespace) -> int:

    import yaml

    text = _params_yaml(args.method, args.blocks)
    emit(args, {"method": args.method, "blocks": args.blocks, "params": yaml.safe_load(text)}, text.rstrip("\n"))
    return 0


def _block_list(text: str) -> list[int]:
    out = []
    for part in text.split(","):
        try:
            n = int(part)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a comma list of block counts, got {text!r}") from None
        if not 2 <= n <= 5:
            raise argparse.ArgumentTypeError(f"block counts must be 2..5, got {n}")
        out.append(n)
    return list(dict.fromkeys(out))


def _register_experiment(sub: argparse._SubParsersAction, methods: tuple[str, ...]) -> None:
    p = command_parser(sub, "experiment", "Figure 7: test-task curves of the learners over cycles",
                       "csql-sim experiment --cycles 10 --out fig7")
    from csql_sim.learners.training import PAPER_METHODS

    p.add_argument("--methods", type=_methods, default=list(PAPER_METHODS),
                   help=f"comma list of {','.join(methods)} (default the paper's {','.join(PAPER_METHODS)})")
    p.add_argument("--cycles", type=positive_int, default=50, help="cycles per method (default 50)")
    p.add_argument("--trials", type=non_negative_int, default=None,
                   help="trials per cycle (default by n: 2500 for n <= 3, 20000 for n = 4 and 5)")
    p.add_argument("--seed", type=seed_arg, default=0, help="root seed (default 0)")
    add_workers(p, "processes, or CPUs of a local Ray instance")
    add_backend_arguments(p)
    p.add_argument("--blocks", type=blocks_arg, default=3,
                   help=blocks_help(2, 6, 3, "; for n != 3 the test task is a pair of maximal optimal length"))
    p.add_argument("--params", type=path_arg, help="YAML parameter overrides (flat, or keyed by method)")
    p.add_argument("--out", type=path_arg, required=True,
                   help="folder for figure7.csv, figure7.json (provenance), figure7.png")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_experiment, declare=lambda args, outputs: declare_folder(args, outputs, FIGURE7_FILES))

def _register_train(sub: argparse._SubParsersAction, methods: tuple[str, ...]) -> None:
    p = command_parser(sub, "train", "train one agent and save its classifier list",
                       "csql-sim train --method cs-ql --blocks 3 --out rules.yaml")
    p.add_argument("--method", choices=methods, default="cs-ql", help="learner (default cs-ql)")
    p.add_argument("--trials", type=non_negative_int, default=None,
                   help="training trials (default by n: 2500 for n <= 3, 20000 for n = 4 and 5)")
    p.add_argument("--seed", type=seed_arg, default=None, help="seed (default 0)")
    p.add_argument("--blocks", type=train_blocks_arg, default=None,
                   help=blocks_help(2, 6, 3, "; 7 only with --dry-run, to see the estimate"))
    p.add_argument("--params", type=path_arg, help="YAML parameter overrides (on top of the defaults for n)")
    p.add_argument("--engine", choices=("fast", "reference"), default=None,
                   help="engine of cs-ql and lt-ql: fast (their default; cs-ql with the built-in rules, lt-ql up "
                   "to 5 blocks) or reference; the same rule file")
    add_domain_rules(p, "R-classifiers from this rule file (e.g. from 'discover') instead of Figure 5 (was --domain)")
    p.add_argument("--sweep", choices=("none", "value-iteration"), default=None,
                   help="cs-ql/xcs-ql after the trials: value-iteration (the default; greedy passes over every pair "
                   "through the world model, backing up every candidate for n > 3) or none (learn from trials "
                   "alone); sets the parameter sweep")
    p.add_argument("--replay", type=replay_ratio_arg, default=None,
                   help="cs-ql: replay the transitions trials experienced (each for every goal), at most R replay "
                   "backups per experienced step, R >= 0 (default 0: no replay; reference engine); sets replay_ratio")
    p.add_argument("--out", type=path_arg, default=None,
                   help="rule file to write: *.npz (compact) or YAML; a directory for a sharded run (optional "
                        "with --dry-run, which checks it as the run would)")
    add_size_arguments(p)
    add_overwrite(p)
    add_quiet(p)
    if "--json" not in p._option_string_actions:
        add_json(p)
    p.set_defaults(func=cmd_train, declare=_declare_train)


def _declare_train(args: argparse.Namespace, outputs: Outputs) -> None:
    from csql_sim.cli import train_shards

    train_shards.settle(args)
    if args.out is None and not args.dry_run:
        raise CsqlError("train needs --out FILE (a rule file, or a directory for a sharded run)")
    if args.out is None:  # --dry-run: the estimate only
        outputs.input(getattr(args, "params", None), "parameter file")
        return
    (train_shards.declare if train_shards.sharded(args) else declare_rule_file)(args, outputs)

def _register_scaling(sub: argparse._SubParsersAction, methods: tuple[str, ...]) -> None:
    p = command_parser(sub, "scaling", "trials until every pair is planned optimally, per n and method "
                       "(with each cell's wall time and peak resident memory)",
                       "csql-sim scaling --blocks 3,4 --out scaling")
    p.add_argument("--blocks", type=_block_list, default=[3, 4, 5], help="comma list of n, 2..5 (default 3,4,5)")
    p.add_argument("--methods", type=_methods, default=["lt-ql", "cs-ql"], help="comma list (default lt-ql,cs-ql)")
    p.add_argument("--modes", type=modes_arg, default=["trials", "replay", "sweep"],
                   help="comma list of cs-ql's modes: trials (alone), replay (of their experience), sweep (value "
                   "iteration through the world model) (default all three)")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed (default 0)")
    p.add_argument("--max-trials", type=positive_int, default=20_000, help="cap per (n, method) (default 20000)")
    p.add_argument("--workers", type=positive_int, default=1,
                   help="cells at once: processes, or CPUs of a local Ray instance (default 1: one after another, "
                   "so that no two timed cells share the cores)")
    add_backend_arguments(p)
    p.add_argument("--out", type=path_arg, required=True,
                   help="folder for scaling.csv, scaling.json (provenance) and scaling.png")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_scaling, declare=lambda args, outputs: declare_folder(args, outputs, SCALING_FILES))

def _register_bench(sub: argparse._SubParsersAction, methods: tuple[str, ...]) -> None:
    p = command_parser(sub, "bench", "time both engines of CS-QL and of LT-QL, and a plain dict-based Q-learner, "
                       "on the same trials", "csql-sim bench --repeats 5")
    p.add_argument("--trials", type=non_negative_int, default=2500, help="training trials (default 2500)")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed (default 0)")
    p.add_argument("--repeats", type=positive_int, default=15, help="best of this many runs (default 15)")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_bench)

def _register_params(sub: argparse._SubParsersAction, methods: tuple[str, ...]) -> None:
    p = command_parser(sub, "params", "print a learner's default parameters as YAML that --params accepts",
                       "csql-sim params --method cs-ql --blocks 4 > params.yaml")
    p.add_argument("--method", choices=methods, default="cs-ql", help="learner (default cs-ql)")
    p.add_argument("--blocks", type=blocks_arg, default=3, help=blocks_help(2, 6, 3))
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_params)


def _params_yaml(method: str, n: int = 3) -> str:
    """The defaults of ``method`` for n blocks as a flat YAML mapping that ``--params`` accepts.

    A header comment names the package version, the method and n.
    """
    import yaml

    from csql_sim import __version__
    from csql_sim.learners.paper import defaults_for_blocks

    params = defaults_for_blocks(method, n)
    doc = {f.name: getattr(params, f.name) for f in fields(params)}
    head = (f"# csql-sim {__version__}: default parameters of {method} ({type(params).__name__}) for {n} blocks;\n"
            f"# edit and pass with --params FILE (with --blocks {n})\n")
    return head + yaml.safe_dump(doc, sort_keys=False)


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``experiment``, ``train``, ``scaling``, ``bench`` and ``params`` to the subparsers."""
    from csql_sim.learners.training import METHODS

    for add in (_register_experiment, _register_train, _register_scaling, _register_bench, _register_params):
        add(sub, METHODS)


__all__ = ["register"]
