"""``train``'s and ``scaling``'s options for what learns: ``--sweep``, ``--replay``, ``--modes``; the phase report."""

from __future__ import annotations

import argparse

from csql_sim.infra.errors import CsqlError


def train_params(args: argparse.Namespace) -> object:
    """``--params`` with ``--sweep`` and ``--replay`` on top (they override the file's ``sweep``, ``replay_ratio``)."""
    from csql_sim.learners.paper import resolve_params

    overrides = {}
    if args.sweep is not None:
        overrides["sweep"] = args.sweep != "none"
    if args.replay is not None:
        overrides["replay_ratio"] = float(args.replay)
    if not overrides:
        return args.params
    if args.method not in ("cs-ql", "xcs-ql"):
        raise CsqlError(f"--sweep and --replay apply to cs-ql and xcs-ql, not {args.method}")
    from csql_sim.learners.paper import with_overrides

    return with_overrides(resolve_params(args.method, args.params, args.blocks or 3), overrides)


def phase_lines(phases: dict) -> list[str]:
    """What each phase of training contributed (the rule file's ``meta.phases``), one line each."""
    t = phases["trials"]
    seen = (f"; {t['experienced_pairs']:,} of {t['legal_pairs']:,} (state, action) pairs experienced"
            if "experienced_pairs" in t else "")
    lines = [f"after the trials alone: {t['trials']:,} trials, {t['steps']:,} steps{seen}; optimal pairs "
             f"{t['optimal_pairs']:,} of {t['pairs']:,} (optimal first steps {t['optimal_steps']:,})"]
    if "replay" in phases:
        r = phases["replay"]
        lines.append(f"after experience replay: {r['backups']:,} replay backups; optimal pairs "
                     f"{r['optimal_pairs']:,} of {r['pairs']:,}")
    if "sweep" in phases:
        w = phases["sweep"]
        lines.append(f"after the sweep (value iteration through the world model): {w['backups']:,} backups in "
                     f"{w['steps']:,} steps; optimal pairs {w['optimal_pairs']:,} of {w['pairs']:,}")
    else:
        lines.append("no sweep: every figure above comes from the trials" +
                     (" and the replay of their experience" if "replay" in phases else ""))
    return lines


# ------------------------------------------------------------------ bench


def replay_ratio_arg(text: str) -> float:
    """``--replay``: a number in the range of the parameter ``replay_ratio`` (its one declaration)."""
    from csql_sim.learners.paper import CSQLParams

    RATIO = CSQLParams.bounds("replay_ratio")  # noqa: N806 - the declared constant, read where it is declared
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number in {RATIO}, got {text!r}") from None
    if not RATIO.contains(value):
        raise argparse.ArgumentTypeError(f"must be a number in {RATIO}, got {text!r}")
    return value


def modes_arg(text: str) -> list[str]:
    """``scaling --modes``: a comma list of trials, replay, sweep."""
    names = list(dict.fromkeys(m.strip() for m in text.split(",") if m.strip()))
    bad = [m for m in names if m not in ("trials", "replay", "sweep")]
    if bad or not names:
        raise argparse.ArgumentTypeError(f"modes are trials, replay, sweep; got {text!r}")
    return names
