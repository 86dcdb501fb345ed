"""LQ-CS over given atoms and over generated features, both formulations, beside GN1, GN2 and the hand ordering.

Regenerates docs/results/features.md, the table of LQ-CS over given atoms and generated features.

    python benchmarks/features_table.py --explain FILE
    python benchmarks/features_table.py --policy-file FILE --variants generated-4op --seeds 0
    python benchmarks/features_table.py --policy-file 'c_{seed}.json' --variants committee-move --seeds 0-9
    python benchmarks/features_table.py [--seeds 0-9] [--variants given,generated-move,committee-move]
                                    [--use 100] [--sizes 7,10,20,26] [--tall 25,50,100] [--tall-tasks 3]
                                    [--out feature_table.jsonl] [--report]

Pairs: the benchmark's (``benchmarks/lifted_benchmark.py --pairs 1000``: one generator seeded 0
draws 1,000 pairs for n = 6, 7, 8, 10, 15, 20, 26 in turn), of which the first ``--use`` of
each size of ``--sizes`` are planned, against their exact optimum (a yardstick). Tall towers:
``--tall-tasks`` tasks per size of ``--tall`` from the tall-tower generator of ``csql-sim
problems``, drawn in turn by one generator seeded 0 (so a size's tasks depend on the sizes
listed before it: keep ``--tall 25,50,100`` to compare with the docs), against the optimum
of the deadlock characterization, solved by CP-SAT
(the ``bench`` extra) or else by branch and bound within 10 s; where it is not proven, against
its lower bound (flagged).

Every learned variant trains with its defaults from ``np.random.default_rng(seed)``: ``given``
the eight hand-written atoms, ``generated-4op`` and ``generated-move`` one population over
features generated from the predicates of the shipped PDDL domains (``--committee 1``),
``committee-4op`` and ``committee-move`` a committee of three populations over them (what
``csql-sim train-lifted --features generated`` learns by default). A policy of the move domain is run with its moves
executed as a pick and a put, and only its own (hand-empty) states count as revisited.
Figures come from trials and the learner's sweeps through its world model; none from search.

Each (variant, seed) is one JSON line of ``--out``, written when done: a run that is stopped
resumes where it was. Each row records the policy's agreement with the hand ordering
(:func:`csql_sim.core.policies.agreement.agreement`). These tasks are tuning tasks
(:mod:`csql_sim.core.model.task_split`): the learner's K, sweep length, split rule and pick
rule were chosen on them; ``benchmarks/lifted_heldout.py`` measures held-out ones. ``--report``
prints the tables (min / median / max over seeds) of every variant in the file.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from csql_sim.core.features.move_features import literal_values
from csql_sim.core.measure.bounds import bounded_optimum, cpsat_optimum
from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model.task_draws import draw_task
from csql_sim.core.policies.agreement import agreement
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.gn2 import Gn2Policy
from csql_sim.core.policies.hand_ordering import hand_ordering
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.atom_names import ATOMS
from csql_sim.core.state.move_relations import MoveRelations, target_goal
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.learners.lifted.committee import train_committee
from csql_sim.learners.lifted.params import LiftedParams
from csql_sim.learners.lifted.ql import train_lifted

BENCH_SIZES = (6, 7, 8, 10, 15, 20, 26)
VARIANTS = {"given": {}, "generated-4op": {"features": "generated", "domain": "4op"},
            "generated-move": {"features": "generated", "domain": "move"},
            "committee-4op": {"features": "generated", "domain": "4op", "committee": 3},
            "committee-move": {"features": "generated", "domain": "move", "committee": 3}}
FIXED = {"gn1": Gn1Policy, "gn2": Gn2Policy, "hand ordering": hand_ordering}
"""The fixed comparators: the named baselines and the hand ordering over the given atoms, ``cover`` included."""
DEFAULT_VARIANTS = ("given", "generated-4op", "generated-move", "committee-4op", "committee-move")


def tasks(args: argparse.Namespace) -> dict[str, list[tuple]]:
    """Every task measured, by label (``n=7`` ..., ``tall-25`` ...), with its optimum (or bound) and flag."""
    rng = np.random.default_rng(0)
    out: dict[str, list[tuple]] = {}
    for n in BENCH_SIZES:
        pairs = sample_pairs(n, 1000, rng)
        if n in args.sizes:
            out[f"n={n}"] = [(s, g, optimal_length(s, g), True) for s, g in pairs[:args.use]]
    rng = np.random.default_rng(0)
    for n in args.tall:
        rows = []
        for _ in range(args.tall_tasks):
            s, g = draw_task("tall-towers", n, rng)
            bound = exact(s, g)
            rows.append((s, g, bound.lower, bound.proven))
        out[f"tall-{n}"] = rows
    return out


def exact(start, goal):  # noqa: ANN001, ANN201 - states in, a Bound out
    """The optimum by CP-SAT (the bench extra) within 10 s, else by branch and bound; a lower bound if unproven."""
    try:
        return cpsat_optimum(start, goal, 10.0)
    except ImportError:
        return bounded_optimum(start, goal, 10.0)


def measure(policy, data: dict[str, list[tuple]], hand: bool = True) -> dict[str, dict]:
    """Per label: solved %, optimal %, total length / total optimum (or bound) over the solved tasks, seconds."""
    out = {}
    for label, rows in data.items():
        t0 = time.perf_counter()
        runs = [rollout_relational(policy, s, g, hand=hand) for s, g, _, _ in rows]
        solved = [(r.length, o) for r, (_, _, o, _) in zip(runs, rows, strict=True) if r.reached]
        out[label] = {"solved": 100 * len(solved) / len(rows),
                      "optimal": 100 * sum(length == o for length, o in solved) / len(rows),
                      "ratio": sum(length for length, _ in solved) / max(1, sum(o for _, o in solved)),
                      "proven": all(p for _, _, _, p in rows), "seconds": time.perf_counter() - t0}
        print(f"  {label}: {out[label]['solved']:.1f} solved, {out[label]['optimal']:.1f} optimal, "
              f"x{out[label]['ratio']:.3f}", file=sys.stderr, flush=True)
    return out


def run_all(args: argparse.Namespace) -> None:
    """Measure the fixed policies once and every (variant, seed) not yet in ``--out``."""
    done = set()
    if Path(args.out).exists():
        done = {(r["variant"], r["seed"]) for r in map(json.loads, Path(args.out).read_text().splitlines())}
    data = tasks(args)
    jobs = [(name, None) for name in FIXED] + \
        [(v, seed) for v in args.variants for seed in args.seeds]
    if args.policy_file:  # trained files, each measured as the run of its variant and seed
        jobs = [(args.variants[0], seed) for seed in (args.seeds if "{seed}" in args.policy_file else args.seeds[:1])]
    for variant, seed in jobs:
        if (variant, seed) in done:
            continue
        print(f"{variant} seed {seed}", file=sys.stderr, flush=True)
        row: dict = {"variant": variant, "seed": seed}
        if args.policy_file:
            path = args.policy_file.replace("{seed}", str(seed))
            policy = load_policy(path)
            hand = getattr(getattr(policy, "form", None), "hand", True)
            row.update(file=path, classifiers=classifiers(policy))
        elif seed is None:
            policy, hand = FIXED[variant](), True
        else:
            options = dict(VARIANTS[variant])
            size = options.pop("committee", 1)
            rng = np.random.default_rng(seed)
            params = LiftedParams(**options)
            run = train_committee(params, rng, size) if size > 1 else train_lifted(params, rng)
            policy = run.policy()
            hand = getattr(getattr(policy, "form", None), "hand", True)
            members = getattr(run, "members", (run,))
            row.update(training_seconds=run.seconds, classifiers=classifiers(policy),
                       literals=[lit.words() for m in getattr(policy, "members", (policy,))
                                 for lit in getattr(m, "literals", ())],
                       features=[m.features for m in members] if size > 1 else run.features)
        row["results"] = measure(policy, data, hand)
        row["agreement"] = agreement(policy).as_dict()
        with open(args.out, "a") as f:
            f.write(json.dumps(row) + "\n")


def classifiers(policy) -> int:  # noqa: ANN001 - any lifted policy
    """The policy's classifiers, over all members of a committee."""
    return sum(len(m.classifiers) for m in getattr(policy, "members", (policy,)))


def explain(path: str, pairs: int = 300) -> list[str]:
    """Each literal of a generated-features file in words, and the given atom it equals on sampled moves, if any.

    The sample: ``pairs`` (state, goal) pairs of 5, 7 and 10 blocks (seed 0; hand-empty only for a
    domain without a hand), every legal move of each. A literal equals an atom (or its negation)
    when the two take the same value on every sampled move. A committee's members in turn.
    """
    members = getattr(load_policy(path), "members", None)
    if members is None:
        return explain_policy(load_policy(path), pairs)
    return [line for k, m in enumerate(members, 1) for line in (f"member {k}:", *explain_policy(m, pairs))]


def explain_policy(policy, pairs: int) -> list[str]:  # noqa: ANN001 - a FeaturePolicy
    """The lines of :func:`explain` for one population."""
    rng = np.random.default_rng(0)
    cols: list[np.ndarray] = []
    atoms: list[np.ndarray] = []
    for n in (5, 7, 10):
        for s, g in sample_pairs(n, pairs, rng):
            if not policy.form.hand and (s.held is not None or g.held is not None):
                continue
            t = target_goal(s, g)
            rel = MoveRelations(s, t)
            options, values = literal_values(policy.literals, policy.form, s, t, rel.moves)
            cols.append(values)
            atoms.append(np.array([rel.bits(m) for m in options], np.uint8).reshape(len(options), len(ATOMS)))
    lit, atom = np.concatenate(cols), np.concatenate(atoms)
    lines = []
    for j, literal in enumerate(policy.literals):
        same = [a for k, a in enumerate(ATOMS) if (lit[:, j] == atom[:, k]).all()]
        negated = [f"not {a}" for k, a in enumerate(ATOMS) if (lit[:, j] != atom[:, k]).all()]
        equal = ", ".join(same + negated) or "no given atom"
        lines.append(f"{j + 1}. `{literal.words()}` ({equal})")
    return lines


def spread(values: list[float], fmt: str = "{:.1f}") -> str:
    """min / median / max (one value when all are equal)."""
    parts = [min(values), statistics.median(values), max(values)]
    return fmt.format(parts[0]) if len(set(parts)) == 1 else " / ".join(fmt.format(v) for v in parts)


def report(args: argparse.Namespace) -> None:
    """The tables: per label and variant, solved, optimal, length / optimum (min / median / max over seeds)."""
    rows = [json.loads(x) for x in Path(args.out).read_text().splitlines()]
    labels = list(rows[0]["results"])
    print("| tasks | policy | seeds | agreement | solved % | optimal % | length / optimum |")
    print("|---|---|---|---|---|---|---|")
    for label in labels:
        for variant in dict.fromkeys([*FIXED, *VARIANTS, *(r["variant"] for r in rows)]):
            mine = [r for r in rows if r["variant"] == variant and label in r["results"]]
            if not mine:
                continue
            res = [r["results"][label] for r in mine]
            seeds = "-" if mine[0]["seed"] is None else f"{len(mine)}"
            bound = "" if all(x["proven"] for x in res) else " (bound)"
            ratios = [x["ratio"] for x in res if x["solved"]]  # over the solved tasks: none solved, no ratio
            ratio = spread(ratios, "{:.3f}") + bound if ratios else "-"
            shares = [100 * r["agreement"]["share"] for r in mine if "agreement" in r]
            agreed = spread(shares) + "%" if shares else "-"
            print(f"| {label} | {variant} | {seeds} | {agreed} | {spread([x['solved'] for x in res])} | "
                  f"{spread([x['optimal'] for x in res])} | {ratio} |")


def main(argv: list[str] | None = None) -> int:
    """Run, or report."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ints = lambda t: [int(x) for x in t.split(",") if x]  # noqa: E731
    parser.add_argument("--seeds", default="0-9", help="seeds, a range a-b or a comma list (default 0-9)")
    parser.add_argument("--variants", default=",".join(DEFAULT_VARIANTS),
                        help=f"learned variants among {', '.join(VARIANTS)} (default: {', '.join(DEFAULT_VARIANTS)}; "
                             "a committee-* variant trains a committee of three populations)")
    parser.add_argument("--use", type=int, default=100, help="benchmark pairs planned per n (default 100)")
    parser.add_argument("--sizes", type=ints, default=[7, 10, 20, 26], help="benchmark sizes (default 7,10,20,26)")
    parser.add_argument("--tall", type=ints, default=[25, 50, 100], help="tall-tower sizes (default 25,50,100)")
    parser.add_argument("--tall-tasks", type=int, default=3, help="tall-tower tasks per size (default 3)")
    parser.add_argument("--out", default="feature_table.jsonl", help="results, one JSON line per run")
    parser.add_argument("--report", action="store_true", help="print the tables of --out and stop")
    parser.add_argument("--policy-file", help="measure this trained file as the run of the first variant and seed "
                        "(made by csql-sim train-lifted with that variant's options and seed); with {seed} in "
                        "the name, the file of each seed of --seeds")
    parser.add_argument("--explain", metavar="FILE", help="print the literals of a generated-features file in words")
    args = parser.parse_args(argv)
    if args.explain:
        print("\n".join(explain(args.explain)))
        return 0
    if args.report:
        report(args)
        return 0
    a, _, b = args.seeds.partition("-")
    args.seeds = list(range(int(a), int(b) + 1)) if b else [int(x) for x in args.seeds.split(",")]
    args.variants = [v for v in args.variants.split(",") if v]
    unknown = set(args.variants) - set(VARIANTS)
    if unknown:
        parser.error(f"unknown variants {', '.join(sorted(unknown))}; known: {', '.join(VARIANTS)}")
    run_all(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
