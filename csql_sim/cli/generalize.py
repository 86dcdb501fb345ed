"""``csql-sim generalize``: a trained rule base as a small default hierarchy of ``#`` Q-classifiers."""

from __future__ import annotations

import argparse

from csql_sim.cli.args import add_json, add_overwrite, add_quiet, command_parser, path_arg, rules_arg, show_progress
from csql_sim.cli.output import emit
from csql_sim.infra.outputs import Outputs


def _detectors(text: str) -> tuple[str, ...]:
    from csql_sim.core.state.goal_message import DETECTORS

    if text.strip().lower() == "none":
        return ()
    names = tuple(d.strip().lower() for d in text.split(",") if d.strip())
    for d in names:
        if d not in DETECTORS:
            raise argparse.ArgumentTypeError(f"unknown detector {d!r}; choose from {','.join(DETECTORS)} or none")
    return tuple(d for d in DETECTORS if d in names)


def declare(args: argparse.Namespace, outputs: Outputs) -> None:
    """One rule file written; the rule file read is an input."""
    outputs.file(args.out, "rule file", "rules")
    outputs.input(args.rules, "rule file")


def cmd_generalize(args: argparse.Namespace) -> int:
    from csql_sim.core.files.rulebase import file_bytes
    from csql_sim.infra.files import write_or_keep
    from csql_sim.learners.generalize import generalize

    rulebase = generalize(args.rules, args.detectors, progress=show_progress(args))
    path = write_or_keep([(args.out, file_bytes(args.out, rulebase))])[0]
    meta = rulebase.meta
    doc = {"blocks": rulebase.blocks, "q_before": meta["source"]["q_classifiers"],
           "pairs_decided": meta["pairs_decided"], "q_after": len(rulebase.classifiers),
           "detectors": list(meta["detectors"]), "out": str(path)}
    emit(args, doc, f"{doc['q_before']} Q-classifiers ({rulebase.blocks} blocks, {meta['pairs_decided']} pairs "
                    f"decided) compacted into {doc['q_after']} goal-form Q-classifiers "
                    f"(detectors: {','.join(meta['detectors']) or 'none'}); wrote {path}")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``generalize`` to the subparsers."""
    p = command_parser(sub, "generalize", "compact a trained rule base into a default hierarchy of # "
                       "Q-classifiers over the goal form of the message",
                       "csql-sim generalize --rules rules.yaml --out general.yaml")
    p.add_argument("--rules", type=rules_arg, required=True, help="a trained rule file (index form, YAML or npz)")
    p.add_argument("--out", type=path_arg, required=True, help="rule file to write: *.npz (compact) or YAML")
    p.add_argument("--detectors", type=_detectors, default=None,
                   help="comma list of detector fields in the message: home, placed, ready (default all), or none")
    add_overwrite(p)
    add_quiet(p)
    add_json(p)
    p.set_defaults(func=cmd_generalize, declare=declare)
