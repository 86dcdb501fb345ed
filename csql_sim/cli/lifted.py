"""``csql-sim train-lifted``: learn lifted Q-classifiers on small worlds (LQ-CS), for plans up to 26 blocks."""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

from csql_sim.cli.args import (
    ALIASES_UNTIL,
    add_json,
    add_quiet,
    add_seed,
    add_workers,
    command_parser,
    int_type,
    path_arg,
    show_progress,
    warn_workers,
)
from csql_sim.cli.output import emit
from csql_sim.core.files.pddl_import import MAX_PLANNED_BLOCKS
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import Outputs

if TYPE_CHECKING:
    from csql_sim.learners.lifted import LiftedRun


def _sizes(text: str) -> tuple[int, ...]:
    """A comma list of training sizes, each 3..5."""
    try:
        sizes = tuple(sorted({int(x) for x in text.split(",") if x.strip()}))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected sizes such as 5 or 3,4,5, got {text!r}") from None
    if not sizes or any(n not in (3, 4, 5) for n in sizes):
        raise argparse.ArgumentTypeError(f"training sizes must be among 3, 4, 5 (small worlds only), got {text!r}")
    return sizes


def declare(args: argparse.Namespace, outputs: Outputs) -> None:
    """One lifted Q-classifier file written."""
    outputs.file(args.out, "lifted Q-classifier file", "rules")
    from csql_sim.core.features.formulation import BUILTIN

    if args.domain not in (None, *BUILTIN):
        outputs.input(args.domain, "PDDL domain")


def _ignored(args: argparse.Namespace) -> dict[str, str]:
    """The options of generated features without them, and ``--workers`` with one population."""
    out = {}
    if args.features != "generated":
        out = {k: "--features generated" for k in ("domain", "formulation", "complexity")}
    if args.features != "generated" or args.committee == 1:
        out["workers"] = "--features generated and a committee of two or more (--committee K)"
    return out


DEFAULT_COMMITTEE = 3
"""Populations a run over generated features learns by default (``docs/features.md``: every seed's committee of
three is above GN1 at n = 20, where one population's median is below it)."""


def _progress(args: argparse.Namespace) -> Callable[[int, int], None] | None:
    """A bar of the trials on stderr (a terminal, not --quiet), moved after every sweep or finished member."""
    if not show_progress(args):
        return None
    from tqdm import tqdm

    bars: list[tqdm] = []

    def report(done: int, total: int) -> None:
        if not bars:
            bars.append(tqdm(total=total, desc="trials", unit="trial", delay=1.0, leave=False))
        bars[0].update(done - bars[0].n)
        if done >= total:
            bars[0].close()

    return report


def _training(run: LiftedRun) -> dict:
    """What one population's training did and cost, for the file's ``meta``."""
    training = {"trials": run.trials, "steps": run.steps, "seconds": round(run.seconds, 1), "reached": run.reached,
                "ground_q_classifiers": run.ground, "covered": run.covered, "specializations": run.splits,
                "generalizations": run.merges, "lifted_q_classifiers": len(run.classifiers)}
    if run.features:
        training["features"] = run.features
    return training


def _summary(run: LiftedRun, sizes: tuple[int, ...]) -> str:
    """One line on a population's training."""
    return (f"LQ-CS: {run.trials} trials on {','.join(map(str, sizes))} blocks, {run.steps} steps, "
            f"{run.seconds:.1f} s; {run.covered} lifted Q-classifiers covered, {run.splits} specialized, "
            f"{run.merges} generalized; {len(run.classifiers)} kept")


def cmd_train_lifted(args: argparse.Namespace) -> int:
    import numpy as np

    from csql_sim.core.policies.committee_policy import dumps_committee
    from csql_sim.core.policies.feature_policy import dumps_feature_policy
    from csql_sim.core.policies.lifted_policy import dumps_lifted_policy
    from csql_sim.infra.files import write_or_keep
    from csql_sim.infra.provenance import provenance
    from csql_sim.learners.lifted import LiftedParams, train_committee, train_lifted

    if args.atoms is not None and args.features == "generated":
        raise CsqlError("--atoms chooses among the given atoms; do not give it with --features generated")
    if args.committee is None:
        args.committee = DEFAULT_COMMITTEE if args.features == "generated" else 1
    if args.committee > 1 and args.features != "generated":
        raise CsqlError("--committee needs --features generated")
    read = {} if args.atoms is None else {"atoms": args.atoms}
    chosen = {} if args.complexity is None else {"complexity": args.complexity}
    params = LiftedParams(trials=args.trials, sizes=args.sizes, goals=args.goals, features=args.features,
                          domain=formulation_of(args), **chosen, **read)
    rng = np.random.default_rng(args.seed)
    if args.committee > 1:
        warn_workers(args)
        runs = train_committee(params, rng, args.committee, progress=_progress(args), workers=args.workers).members
    else:
        runs = (train_lifted(params, rng, progress=_progress(args)),)
    run = runs[0]
    training = _training(run) if len(runs) == 1 else {"committee": len(runs), "members": [_training(r) for r in runs]}
    meta = {"method": "lq-cs", "seed": args.seed, "params": params.as_dict(), "training": training,
            "provenance": provenance(seed=args.seed, params=params, committee=args.committee)}
    if len(runs) > 1:
        text = dumps_committee([(r.classifiers, r.literals) for r in runs], run.domain,
                               run.features["formulation"], meta)
    elif run.literals:
        text = dumps_feature_policy(run.classifiers, run.literals, run.domain, run.features["formulation"], meta)
    else:
        text = dumps_lifted_policy(run.classifiers, meta)
    path = write_or_keep([(args.out, text)])[0]
    written = json.loads(text)  # what --json reports of the classifiers is what the file holds
    learned = {k: written[k] for k in ("atoms", "classifiers", "members") if k in written}
    emit(args, {**meta, **learned, "written": str(path)}, lambda: [
        *(line for k, r in enumerate(runs, 1) for line in _lines(r, params.sizes, k if len(runs) > 1 else 0)),
        f"wrote {path}"])
    return 0


def _lines(run: LiftedRun, sizes: tuple[int, ...], member: int) -> list[str]:
    """The text lines on one population: its training, classifiers and literals (``member`` 0: no committee)."""
    policy = run.policy()
    head = [f"member {member}:"] if member else []
    return [*head, _summary(run, sizes), *(f"  {c.text()}" for c in policy.classifiers),
            *(f"  literal {j + 1}: {lit.words()}" for j, lit in enumerate(getattr(policy, "literals", ())))]


def _atoms(text: str) -> tuple[str, ...]:
    """A comma list of given atoms by name, with or without their arguments, or ``all``."""
    from csql_sim.core.state.move_relations import ATOMS

    short = {a.split("(")[0]: a for a in ATOMS}
    names = [w.strip() for w in text.split(",")]
    if names == ["all"]:
        return ATOMS
    bad = [w for w in names if w not in short and w not in ATOMS]
    if bad or not names:
        raise argparse.ArgumentTypeError(f"unknown atom {bad[0] if bad else text!r}; expected a comma list "
                                         f"among {','.join(short)}, or all")
    return tuple(a for a in ATOMS if a in names or a.split("(")[0] in names)


def _domain(text: str) -> str:
    """A readable PDDL domain file (or, deprecated, a shipped formulation's name: see :class:`_DomainOption`)."""
    from csql_sim.core.features.formulation import BUILTIN

    if text in BUILTIN or os.path.isfile(text):
        return text
    raise argparse.ArgumentTypeError(f"expected a PDDL domain file, got {text!r} (a shipped formulation is "
                                     f"--formulation {'|'.join(BUILTIN)})")


class _DomainOption(argparse.Action):
    """``--domain FILE``: a PDDL domain; ``--domain 4op|move``, the old spelling of ``--formulation``, warns once."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: object,
                 option_string: str | None = None) -> None:  # noqa: D102
        from csql_sim.core.features.formulation import BUILTIN

        if values in BUILTIN:
            print(f"{parser.prog}: warning: --domain {values} is deprecated and goes in {ALIASES_UNTIL}; use "
                  f"--formulation {values}", file=sys.stderr)
            namespace.formulation = values
            return
        namespace.domain = values


def formulation_of(args: argparse.Namespace) -> str:
    """The formulation trained: ``--formulation`` (default 4op) or the PDDL file of ``--domain``, not both."""
    if args.domain is not None and args.formulation is not None:
        raise CsqlError(f"give --formulation {args.formulation} or --domain {args.domain!r} (a PDDL domain), not both")
    return args.domain or args.formulation or "4op"


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``train-lifted`` to the subparsers."""
    p = command_parser(sub, "train-lifted", "learn lifted Q-classifiers on small worlds (their plans: up to "
                       f"{MAX_PLANNED_BLOCKS:,} objects with 'plan --problem')",
                       "csql-sim train-lifted --out lifted.json")
    p.add_argument("--out", type=path_arg, required=True, help="lifted Q-classifier file to write (JSON)")
    p.add_argument("--trials", type=int_type(1, 10**7), default=3000, help="training trials (default 3000)")
    p.add_argument("--sizes", type=_sizes, default=(5,),
                   help="numbers of blocks of the worlds trained on, a comma list among 3,4,5 (default 5)")
    p.add_argument("--goals", type=int_type(1, 10**6), help="training goals per size (default 40; 200 with "
                   "--features generated --formulation move)")
    p.add_argument("--features", choices=("given", "generated"), default="given",
                   help="what the classifiers read: hand-written atoms (given, the default; see --atoms) or features "
                        "generated from the domain's predicates")
    p.add_argument("--atoms", type=_atoms,
                   help="with the given atoms: the ones the classifiers read, a comma list among misplaced,goal-on,"
                        "ready,deadlocked,above-needed,least-stuck,deadlock,holding,cover, or all (default: all but "
                        "least-stuck)")
    p.add_argument("--formulation", choices=("4op", "move"), default=None,
                   help="with --features generated: the shipped formulation, 4op (default) or move")
    p.add_argument("--domain", type=_domain, default=None, action=_DomainOption, metavar="FILE",
                   help="with --features generated: a PDDL domain file to generate the features from, instead of "
                        "--formulation")
    p.add_argument("--complexity", type=int_type(1, 10), default=None,
                   help="with --features generated: the feature grammar's complexity bound K (default 8)")
    p.add_argument("--committee", type=int_type(1, 9), default=None,
                   help="with --features generated: populations learned apart from the seed, whose mean advantage "
                        f"ranks a move when planning (default {DEFAULT_COMMITTEE}; 1 learns one population)")
    add_workers(p, "with --committee: processes that train members at once")
    add_seed(p, "seed of the run's one generator")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_train_lifted, declare=declare, ignored=_ignored)
