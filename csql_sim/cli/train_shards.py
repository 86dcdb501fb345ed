"""``train``'s size options: goal shards, workers and backend, ``--resume``, and the estimate that refuses up front."""

from __future__ import annotations

import argparse
from pathlib import Path

from csql_sim.cli.args import (
    add_backend_arguments,
    add_workers,
    backend_from_args,
    positive_int,
    say,
    show_progress,
)
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import Outputs

RULE_SUFFIXES = (".npz", ".yaml", ".yml")


def add_size_arguments(p: argparse.ArgumentParser) -> None:
    """The size options: shards, workers, backend and address, resume, dry run, memory limit, force."""
    p.add_argument("--shards", type=positive_int, default=None,
                   help="train cs-ql in this many shards of goals into the directory --out (default: 64 at 6 "
                        "blocks, one engine and one rule file below); the result does not depend on --workers")
    add_workers(p, "processes training shards at once, or CPUs of a local Ray instance")
    add_backend_arguments(p)
    p.add_argument("--resume", action="store_true", help="continue the incomplete sharded rule base at --out")
    p.add_argument("--dry-run", action="store_true",
                   help="print the memory, disk and time estimate and exit: 0 if the job fits, 2 if refused")
    p.add_argument("--max-memory", default=None, help="memory limit of the estimate, e.g. 4G (default: available)")
    p.add_argument("--force", action="store_true", help="train even when the estimate says the job cannot fit")


def sharded(args: argparse.Namespace) -> bool:
    """Whether this ``train`` writes a sharded rule base (a directory)."""
    from csql_sim.learners.training import default_shards

    return args.resume or args.shards is not None or default_shards(args.blocks) > 1


def declare(args: argparse.Namespace, outputs: Outputs) -> None:
    """A sharded rule base is a folder (its files are checked before work by :func:`check_directory`)."""
    if args.out is not None:
        outputs.folder(args.out, "sharded rule base")
    outputs.input(getattr(args, "params", None), "parameter file")


def settle(args: argparse.Namespace) -> None:
    """Fill ``--blocks`` (3) and ``--seed`` (0) when not given; with ``--resume``, from the directory (once)."""
    if getattr(args, "settled", False):
        return
    if args.resume:
        adopt_manifest(args)
    args.blocks = 3 if args.blocks is None else args.blocks
    args.seed = 0 if args.seed is None else args.seed
    args.settled = True


def adopt_manifest(args: argparse.Namespace) -> None:
    """``--resume``: continue with what the directory was started with; a different option given is refused."""
    from csql_sim.core.files import rulebase_shards as rs
    from csql_sim.infra.provenance import plain
    from csql_sim.learners.paper import resolve_params

    if not rs.is_sharded(args.out):
        raise CsqlError(f"--resume: {args.out} holds no sharded rule base to continue")
    manifest = rs.read_manifest(Path(args.out))
    for option, key in (("blocks", "blocks"), ("seed", "seed"), ("trials", "trials"), ("shards", "shards")):
        given = getattr(args, option)
        if given is not None and given != manifest.get(key):
            raise CsqlError(f"--resume: {args.out} was started with --{option} {manifest.get(key)}, not {given}; "
                            "give the same options or none")
        setattr(args, option, manifest.get(key))
    try:  # the manifest's parameters must make CS-QL parameters (read_manifest checked the other fields)
        resolve_params("cs-ql", manifest["params"], args.blocks)
    except CsqlError as exc:
        raise CsqlError(f"{Path(args.out) / rs.MANIFEST}: field 'params': {exc}") from None
    if args.params is not None and plain(resolve_params("cs-ql", args.params, args.blocks)) != manifest["params"]:
        raise CsqlError(f"--resume: {args.out} was started with other parameters than {args.params}")
    args.resume_params = manifest["params"]


def check_estimate(args: argparse.Namespace) -> int | None:
    """Estimate the job; refuse it (CsqlError, exit 2) unless it fits or ``--force``.

    Returns:
        With ``--dry-run``, the exit status (0: it fits, 2: it would be refused); else None.
    """
    from csql_sim.core.state.state_count import state_count
    from csql_sim.infra.workers import worker_count
    from csql_sim.learners.training import check_fits, default_shards, estimate, parse_size

    split = sharded(args)
    shards = (args.shards or default_shards(args.blocks)) if split else 1
    states = state_count(args.blocks)
    if not 1 <= shards <= states:
        raise CsqlError(f"--shards must be 1..{states:,} (the goals) at {args.blocks} blocks, got {shards}")
    # the processes the run would start here: a pool, or a local Ray instance (a cluster's own nodes are not here)
    workers = worker_count(args.workers, shards) if args.address is None else args.workers or 1
    est = estimate(args.method, args.blocks, shards, workers, split)
    limit = parse_size(args.max_memory) if args.max_memory is not None else None
    refusal = check_fits(est, args.out if args.out is not None else ".", limit)
    if args.dry_run:
        print(f"estimate: {est.line()}")
        if refusal is not None:
            say(args, "error", refusal)
        return 0 if refusal is None else 2
    if refusal is not None and not args.force:
        raise CsqlError(refusal)
    if refusal is not None:
        say(args, "warning", f"{refusal} (going on: --force)")
    return None


def check_directory(args: argparse.Namespace) -> Path | None:
    """Refuse, before work, a sharded ``--out`` that would replace what this command did not write.

    Returns:
        The directory; None with ``--dry-run`` and no ``--out`` (the options are still checked).
    """
    from csql_sim.core.files import rulebase_shards as rs

    if args.method != "cs-ql" or args.engine == "reference" or args.domain_rules:
        raise CsqlError("sharded training runs cs-ql's array engine with the built-in R-classifiers "
                        "(no --method other than cs-ql, --engine reference or --domain-rules)")
    if args.out is None:  # --dry-run without --out: the estimate alone
        return None
    out = Path(args.out)
    if out.suffix.lower() in RULE_SUFFIXES:
        raise CsqlError(f"--out {args.out}: a sharded rule base is a directory; give a name without {out.suffix}")
    if args.resume:
        if not rs.is_sharded(out):
            raise CsqlError(f"--resume: {args.out} holds no sharded rule base to continue")
        rs.check_own_files(out)  # a link or folder in place of a shard: never written through
        return out
    if out.exists() and not out.is_dir():
        raise CsqlError(f"--out {args.out} is a file; a sharded rule base is a directory")
    rs.check_own_files(out)
    if out.is_dir() and any(out.iterdir()):
        if not args.overwrite:
            what = "a sharded rule base" if rs.is_sharded(out) else "files that are no sharded rule base"
            raise CsqlError(f"--out {args.out} already holds {what}; give --overwrite to replace it, --resume to "
                            "continue a stopped run, or another --out")
        if rs.is_sharded(out):
            rs.read_manifest(out)  # a corrupt manifest is named, not silently replaced
    return out


def run(args: argparse.Namespace, out: Path) -> int:
    """``train`` into the sharded rule base ``out`` (:func:`check_directory`): shards saved as they come back."""
    from csql_sim.learners.paper import default_trials, resolve_params
    from csql_sim.learners.training import ShardRun, default_shards, read_reports, train_sharded

    problem = read_reports(out)[1]  # the reports are not part of the rule base: replaced, and said so after the run
    params = resolve_params("cs-ql", getattr(args, "resume_params", None) or args.params, args.blocks)
    trials = default_trials(args.blocks) if args.trials is None else args.trials
    shards = args.shards or default_shards(args.blocks)
    run_ = ShardRun(out, args.blocks, params, args.seed, trials, shards, backend_from_args(args), args.resume)
    try:
        report = train_sharded(run_, progress=show_progress(args))
    except KeyboardInterrupt as exc:  # Ctrl-C or SIGTERM: say what was kept and how to go on
        raise type(exc)(_kept(out, shards)) from None
    if problem is not None:
        say(args, "warning", f"{problem}; this run's report replaced it")
    peak = report["peak_rss_bytes"]
    print(f"cs-ql (sharded), {args.blocks} blocks: {trials} trials, seed {args.seed}, {shards} shards "
          f"({len(report['shards_trained'])} trained now) in {report['wall_seconds']:.1f} s; optimal pairs "
          f"{report['phases']['trials']['optimal_pairs']:,} after the trials alone, {report['optimal_pairs']:,} "
          f"after the sweep (value iteration, {report['phases']['sweep']['backups']:,} backups) of "
          f"{report['pairs']:,} trained now (against BFS); peak memory: driver "
          f"{peak['driver'] / 2**30:.2f} GB, largest worker {peak['worker_max'] / 2**30:.2f} GB; written to {out}")
    return 0


def _kept(out: Path, shards: int) -> str:
    """After an interruption: the shards saved in ``out`` and how to go on (``--resume`` needs a manifest)."""
    from csql_sim.core.files.rulebase_shards import is_sharded, read_manifest

    if not is_sharded(out):
        return f"no shard saved in {out}; start again with the same command"
    try:
        saved = len(read_manifest(out).get("files", []))
    except CsqlError:
        saved = 0
    return f"{saved} of {shards} shards saved in {out}; continue with: csql-sim train --resume --out {out}"


def train_blocks_arg(text: str) -> int:
    """``train --blocks``: 2..6, and 7 so that the estimate can say what 7 blocks would need."""
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if not 2 <= n <= 7:
        raise argparse.ArgumentTypeError(f"number of blocks must be 2..6 (7: --dry-run estimate only), got {n}")
    return n


def show_sharded(args: argparse.Namespace) -> int:
    """``show DIR --start S --goal G``: Figure 6's table of the greedy path's Q-classifiers, from one shard."""
    from csql_sim.cli.output import emit
    from csql_sim.cli.plan import read_task
    from csql_sim.core.policies.sharded_policy import ShardedPolicy, path_rulebase
    from csql_sim.learners.generalize import figure6_rows, figure6_table

    policy = ShardedPolicy.open(args.rules)
    if args.start is None or args.goal is None:
        raise CsqlError(f"{args.rules} is a sharded rule base ({policy.base.count:,} goals): give --start and --goal "
                        "to show the greedy path's Q-classifiers")
    start, goal = read_task(args.start, args.goal, policy.n)
    rb = path_rulebase(policy, start, goal)
    doc = {"rules": args.rules, "blocks": rb.blocks, "start": start.notation(), "goal": goal.notation(),
           "classifiers": figure6_rows(rb, start, goal), "meta": {"manifest": policy.base.manifest.get("provenance")}}
    emit(args, doc, lambda: figure6_table(rb, start, goal))
    return 0
