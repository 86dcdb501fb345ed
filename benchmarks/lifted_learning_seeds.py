"""LQ-CS over many seeds: solved and optimal % per seed on the benchmark's pairs, beside GN1, GN2 and the hand ordering.

Regenerates docs/results/lifted.md, the table of seeds.

    python benchmarks/lifted_learning_seeds.py [--seeds 0-9] [--trials 3000] [--pairs 1000] [--sizes 7,10,20,26]
                                   [--bench-seed 0] [--bench-sizes 6,7,8,10,15,20,26] [--no-fixed]
                                   [--optima optima.json]

The pairs are the benchmark's (``benchmarks/lifted_benchmark.py``): one generator seeded with
``--bench-seed`` draws ``--pairs`` pairs for every size of ``--bench-sizes`` in turn, and the
sizes of ``--sizes`` are kept, so ``--pairs 1000`` gives exactly the benchmark's pairs. The
exact optimum of each pair is computed once (a yardstick only). For every seed of
``--seeds`` the learner trains with its defaults (``--trials`` aside) from
``np.random.default_rng(seed)``; its training seconds, lifted classifiers and, per n, solved
and optimal % are printed, then minimum / median / maximum over the seeds beside two fixed
policies on the same pairs: ``gn1`` (:mod:`csql_sim.core.policies.gn1`), ``gn2``
(:mod:`csql_sim.core.policies.gn2`), the ``hand ordering`` (six ranks over the given atoms,
``cover`` included: :mod:`csql_sim.core.policies.hand_ordering`) and ``hand-without-cover``
(the older ordering, which leaves ``cover`` out). These pairs are tuning tasks
(:mod:`csql_sim.core.model.task_split`); ``benchmarks/lifted_heldout.py`` measures held-out ones.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.gn2 import Gn2Policy
from csql_sim.core.policies.hand_ordering import hand_ordering, hand_ordering_without_cover
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.learners.lifted.params import LiftedParams
from csql_sim.learners.lifted.ql import train_lifted


def score(policy, pairs: list, optima: list[int]) -> tuple[float, float]:
    """Solved % and optimal % of a policy on the pairs."""
    runs = [rollout_relational(policy, start, goal) for start, goal in pairs]
    solved = sum(r.reached for r in runs)
    optimal = sum(r.reached and r.length == o for r, o in zip(runs, optima, strict=True))
    return 100 * solved / len(pairs), 100 * optimal / len(pairs)


def benchmark_pairs(args: argparse.Namespace) -> dict[int, tuple[list, list[int]]]:
    """The benchmark's pairs of every size of ``--sizes`` and their exact optima (read from ``--optima`` if given)."""
    rng = np.random.default_rng(args.bench_seed)
    known = {}
    if args.optima and Path(args.optima).exists():
        known = json.loads(Path(args.optima).read_text())
    out = {}
    for n in args.bench_sizes:
        pairs = sample_pairs(n, args.pairs, rng)
        if n in args.sizes:
            key = f"seed {args.bench_seed} pairs {args.pairs} sizes {args.bench_sizes} n {n}"
            t0 = time.perf_counter()
            if key not in known:
                known[key] = [optimal_length(s, g) for s, g in pairs]
            out[n] = (pairs, known[key])
            print(f"n = {n}: optimum of {len(pairs)} pairs in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    if args.optima:
        Path(args.optima).write_text(json.dumps(known))
    return out


def spread(values: list[float]) -> str:
    """minimum / median / maximum, one decimal."""
    return f"{min(values):.1f} / {statistics.median(values):.1f} / {max(values):.1f}"


def main(argv: list[str] | None = None) -> int:
    """Train every seed, measure it and the fixed policies, print the tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0-9", help="seeds, a range a-b or a comma list (default 0-9)")
    parser.add_argument("--trials", type=int, default=LiftedParams().trials, help="training trials (default: "
                        "the learner's)")
    parser.add_argument("--pairs", type=int, default=1000, help="pairs per n (default 1000, the benchmark's)")
    parser.add_argument("--sizes", type=lambda t: [int(x) for x in t.split(",")], default=[7, 10, 20, 26],
                        help="numbers of blocks measured (default 7,10,20,26)")
    parser.add_argument("--bench-seed", type=int, default=0, help="seed of the benchmark's generator (default 0)")
    parser.add_argument("--bench-sizes", type=lambda t: [int(x) for x in t.split(",")],
                        default=[6, 7, 8, 10, 15, 20, 26], help="the benchmark's sizes, drawn in turn "
                        "(default 6,7,8,10,15,20,26)")
    parser.add_argument("--optima", help="JSON file of the pairs' exact optima: read if it exists, written after")
    parser.add_argument("--no-fixed", action="store_true", help="measure the learned seeds only, not gn1, gn2 "
                        "and the hand orderings")
    args = parser.parse_args(argv)
    a, _, b = args.seeds.partition("-")
    seeds = list(range(int(a), int(b) + 1)) if b else [int(x) for x in args.seeds.split(",")]
    if not set(args.sizes) <= set(args.bench_sizes):
        parser.error("every size of --sizes must be one of --bench-sizes")
    data = benchmark_pairs(args)
    head = " | ".join(f"n = {n} solved / optimal" for n in args.sizes)
    print(f"| seed | training s | lifted classifiers | {head} |")
    print("|---" * (3 + len(args.sizes)) + "|", flush=True)
    results: dict[int, list[tuple[float, float]]] = {n: [] for n in args.sizes}
    for seed in seeds:
        run = train_lifted(LiftedParams(trials=args.trials), np.random.default_rng(seed))
        policy = run.policy()
        cells = []
        for n in args.sizes:
            results[n].append(score(policy, *data[n]))
            cells.append(f"{results[n][-1][0]:.1f} / {results[n][-1][1]:.1f}")
        print(f"| {seed} | {run.seconds:.1f} | {len(run.classifiers)} | {' | '.join(cells)} |", flush=True)
    print("\n| n | policy | solved % (min / median / max) | optimal % (min / median / max) |")
    print("|---|---|---|---|")
    for n in args.sizes:
        solved, optimal = zip(*results[n], strict=True)
        print(f"| {n} | lq-cs, seeds {args.seeds} | {spread(list(solved))} | {spread(list(optimal))} |")
        fixed_policies = (("gn1", Gn1Policy()), ("gn2", Gn2Policy()), ("hand ordering", hand_ordering()),
                          ("hand-without-cover", hand_ordering_without_cover()))
        for name, fixed in () if args.no_fixed else fixed_policies:
            s, o = score(fixed, *data[n])
            print(f"| {n} | {name} | {s:.1f} | {o:.1f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
