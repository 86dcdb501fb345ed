"""Subcommands ``show`` and ``prune``: a rule file's classifiers, as a table, or pruned into another file.

Both read the file with ``--rules``; the positional form (``csql-sim show r.yaml``) is the
old spelling, kept with a warning until 0.3.0. ``show`` displays every kind of rule file
the tool writes: ground rule bases (Figure 6's table), generalized ones (list order and
coverage), sharded bases (the greedy path's classifiers), lifted Q-classifiers from
``train-lifted`` and lifted rules from ``discover --lifted``.
"""

from __future__ import annotations

import argparse
import os
from typing import TYPE_CHECKING

from csql_sim.cli.args import (
    RULES_BUILTIN_HELP,
    DeprecatedAlias,
    add_json,
    add_overwrite,
    add_quiet,
    command_parser,
    path_arg,
    rules_arg,
    show_progress,
    threshold_arg,
)
from csql_sim.cli.output import emit
from csql_sim.cli.plan import read_task_for_rules
from csql_sim.infra import formats
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import Outputs

if TYPE_CHECKING:
    from csql_sim.core.policies.feature_policy import FeaturePolicy

RULES_HELP = ("a rule file: from 'csql-sim train' (YAML, npz or a sharded directory), 'generalize', "
              "'train-lifted' or 'discover --lifted'" + RULES_BUILTIN_HELP)


def settle_rules(args: argparse.Namespace) -> None:
    """The rule file of ``--rules`` or of the deprecated positional argument (one of them, not both)."""
    old = getattr(args, "rules_positional", None)
    if old is not None and args.rules is not None:
        raise CsqlError(f"give the rule file once: --rules {args.rules} or the positional {old}, not both")
    if old is not None:
        args.rules = old
    if args.rules is None:
        raise CsqlError("give the rule file with --rules FILE")


def declare_show(args: argparse.Namespace, outputs: Outputs) -> None:
    """``show`` reads its rule file: its ``--json FILE`` may not be that file."""
    settle_rules(args)
    outputs.input(args.rules, "rule file")


def declare_prune(args: argparse.Namespace, outputs: Outputs) -> None:
    """``prune`` reads a rule file and writes another."""
    settle_rules(args)
    outputs.file(args.out, "rule file", "rules")
    outputs.input(args.rules, "rule file")


def cmd_show(args: argparse.Namespace) -> int:
    from csql_sim.core.files.rulebase import load
    from csql_sim.core.files.rulebase_shards import is_sharded
    from csql_sim.learners.generalize import figure6_rows, figure6_table

    kind = formats.sniff(args.rules)
    if is_sharded(args.rules):  # read lazily (its manifest checked and named if corrupt): the greedy path only
        from csql_sim.cli.train_shards import show_sharded

        return show_sharded(args)
    if kind in (formats.LIFTED_Q, formats.LIFTED_RULES):
        return show_lifted(args, kind)
    rb = load(args.rules, progress=show_progress(args))
    if (args.start is None) != (args.goal is None):
        raise CsqlError("show needs both --start and --goal, or neither")
    start = goal = None
    if args.start is not None:
        start, goal = read_task_for_rules(args.start, args.goal, rb.blocks, args.rules)
    task = {"start": start.notation() if start else None, "goal": goal.notation() if goal else None}
    if rb.meta.get("form") == "goal":  # generalized Q-classifiers: list order and coverage (learners/paper/coverage.py)
        from csql_sim.learners.paper import coverage_rows, coverage_table

        rows = coverage_rows(rb, start, goal)
        doc = {"rules": args.rules, "blocks": rb.blocks, **task, "classifiers": rows, "meta": rb.meta}
        emit(args, doc, lambda: coverage_table(rows))
        return 0
    doc = {"rules": args.rules, "blocks": rb.blocks, **task, "classifiers": figure6_rows(rb, start, goal),
           "meta": rb.meta}
    emit(args, doc, lambda: figure6_table(rb, start, goal))
    return 0


def show_lifted(args: argparse.Namespace, kind: str) -> int:
    """``show`` of a lifted file: its classifiers (or rules), one line each, and where they came from."""
    if args.start is not None or args.goal is not None:
        raise CsqlError(f"{args.rules} is a {kind} file, shown whole; --start/--goal pick the greedy path of a "
                        f"ground rule base (plan a task with 'csql-sim plan --rules {args.rules}')")
    extra: dict = {}
    if kind == formats.LIFTED_Q:
        from csql_sim.core.policies.agreement import agreement
        from csql_sim.core.policies.feature_policy import FeaturePolicy
        from csql_sim.core.policies.loader import load_policy
        from csql_sim.core.state.atom_names import ATOMS

        policy = load_policy(args.rules)
        meta, field = policy.meta, "classifiers"
        agreed = agreement(policy)
        extra = {"agreement": agreed.as_dict()}
        if isinstance(policy, FeaturePolicy):
            lines = _feature_lines(policy)
            head = ["lifted Q-classifiers over features generated from the domain's predicates (1: holds, 0: does "
                    "not, #: either), then their literals; the move of least advantage is taken"]
        else:
            lines = [c.text() for c in policy.classifiers]
            head = [f"{len(lines)} lifted Q-classifiers over the relations of a move {', '.join(ATOMS)}",
                    "(1: holds, 0: does not, #: either); the move of least advantage is taken"]
    else:
        from csql_sim.core.classifiers.lifted_rule import load_lifted

        lines, meta, field = [r.text() for r in load_lifted(args.rules)], {}, "rules"
        head = [f"{len(lines)} lifted R-classifiers (they ground to the R-classifiers of any n)"]
    doc = {"rules": os.fspath(args.rules), "kind": kind, field: lines, "meta": meta, **extra}
    tail = [agreed.describe()] if extra else []
    emit(args, doc, lambda: [*head, *(f"  {line}" for line in lines), *tail])
    return 0


def _feature_lines(policy: FeaturePolicy) -> list[str]:
    """A generated-features file's classifiers and literals in words, member by member for a committee."""
    members = getattr(policy, "members", (policy,))
    lines = [f"a committee of {len(members)} populations; a move's rank is its mean advantage"] \
        if len(members) > 1 else []
    for k, member in enumerate(members, 1):
        lines += [f"member {k}:"] if len(members) > 1 else []
        lines += [c.text() for c in member.classifiers]
        lines += [f"literal {j + 1}: {lit.words()}" for j, lit in enumerate(member.literals)]
    return lines


def cmd_prune(args: argparse.Namespace) -> int:
    from csql_sim.core.files.rulebase import file_bytes, load
    from csql_sim.infra.files import write_or_keep
    from csql_sim.learners.generalize import count_q, prune

    rb = load(args.rules, progress=show_progress(args))
    pruned = prune(rb, args.threshold)
    path = write_or_keep([(args.out, file_bytes(args.out, pruned))])[0]
    doc = {"threshold": args.threshold, "q_before": count_q(rb), "q_after": count_q(pruned), "out": str(path)}
    emit(args, doc, f"Q-classifiers: {doc['q_before']} before, {doc['q_after']} after pruning at "
                    f"{args.threshold:g}; wrote {path}")
    return 0


def _add_rules(p: argparse.ArgumentParser) -> None:
    p.add_argument("--rules", type=rules_arg, default=None, help=RULES_HELP)
    p.add_argument("rules_positional", nargs="?", type=rules_arg, metavar="RULES", action=DeprecatedAlias,
                   new="--rules RULES", help="the same as --rules RULES (deprecated: goes in 0.3.0)")


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``show`` and ``prune`` to the subparsers."""
    p = command_parser(sub, "show", "print a rule file's classifiers: Figure 6's table, a generalized file in "
                       "list order with the pairs each decides, or a lifted file's lines",
                       "csql-sim show --rules rules.yaml --start CBA --goal BAC")
    _add_rules(p)
    p.add_argument("--start", help="with --goal: show just the greedy path's classifiers (ground rule bases)")
    p.add_argument("--goal", help="goal configuration, e.g. BAC")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_show, declare=declare_show)

    p = command_parser(sub, "prune", "remove Q-classifiers below a strength threshold",
                       "csql-sim prune --rules rules.yaml --out pruned.yaml")
    _add_rules(p)
    p.add_argument("--threshold", type=threshold_arg, default=0.1, help="strength threshold in [0, 1] (default 0.1)")
    p.add_argument("--out", type=path_arg, required=True, help="rule file to write (not the rule file read)")
    add_overwrite(p)
    add_quiet(p)
    add_json(p)
    p.set_defaults(func=cmd_prune, declare=declare_prune)


__all__ = ["register"]
