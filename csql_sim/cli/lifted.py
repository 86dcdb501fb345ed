"""``csql-sim train-lifted``: lifted Q-classifiers learned on small worlds by :func:`csql_sim.api.train_lifted`."""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

from csql_sim.api.running import DEFAULT_COMMITTEE
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


def _summary(run: LiftedRun, sizes: tuple[int, ...]) -> str:
    """One line on a population's training."""
    return (f"LQ-CS: {run.trials} trials on {','.join(map(str, sizes))} blocks, {run.steps} steps, "
            f"{run.seconds:.1f} s; {run.covered} lifted Q-classifiers covered, {run.splits} specialized, "
            f"{run.merges} generalized; {len(run.classifiers)} kept")


def cmd_train_lifted(args: argparse.Namespace) -> int:
    """Learn with :func:`csql_sim.api.train_lifted`, write ``--out``, report what was learned."""
    from csql_sim.api import train_lifted

    if args.atoms is not None and args.features == "generated":
        raise CsqlError("--atoms chooses among the given atoms; do not give it with --features generated")
    if args.committee is None:
        args.committee = DEFAULT_COMMITTEE if args.features == "generated" else 1
    if args.committee > 1 and args.features != "generated":
        raise CsqlError("--committee needs --features generated")
    formulation_of(args)  # --formulation or --domain, not both (the message in the options' names)
    if args.committee > 1:
        warn_workers(args)
    learned = train_lifted(args.out, trials=args.trials, sizes=args.sizes, goals=args.goals, features=args.features,
                           formulation=args.formulation, domain=args.domain, complexity=args.complexity,
                           committee=args.committee, atoms=args.atoms, seed=args.seed, workers=args.workers,
                           progress=_progress(args))
    runs, sizes = learned.runs, tuple(learned.meta["params"]["sizes"])
    written = json.loads(learned.text)  # what --json reports of the classifiers is what the file holds
    classifiers = {k: written[k] for k in ("atoms", "classifiers", "members") if k in written}
    emit(args, {**learned.meta, **classifiers, "written": str(learned.path)}, lambda: [
        *(line for k, r in enumerate(runs, 1) for line in _lines(r, sizes, k if len(runs) > 1 else 0)),
        f"wrote {learned.path}"])
    return 0


def _lines(run: LiftedRun, sizes: tuple[int, ...], member: int) -> list[str]:
    """The text lines on one population: its training, classifiers and literals (``member`` 0: no committee)."""
    policy = run.policy()
    head = [f"member {member}:"] if member else []
    return [*head, _summary(run, sizes), *(f"  {c.text()}" for c in policy.classifiers),
            *(f"  literal {j + 1}: {lit.words()}" for j, lit in enumerate(getattr(policy, "literals", ())))]


def _atoms(text: str) -> tuple[str, ...]:
    """A comma list of given atoms by name, with or without their arguments, or ``all``."""
    from csql_sim.core.state.atom_names import ATOMS

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
