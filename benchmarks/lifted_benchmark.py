"""Lifted policies on random start/goal pairs of 6..26 blocks, measured against the exact optimum.

Regenerates docs/results/lifted.md, the lifted policies against the exact optimum (cited by
docs/results/large_problems.md too).

    python benchmarks/lifted_benchmark.py [--pairs 1000] [--seed 0] [--sizes 6,7,8,10,15,20,26]
                                       [--rules assets/rules/lifted.json]

Per n, K ordered pairs of distinct states are drawn uniformly by counting
(:func:`csql_sim.core.state.state_count.sample_pairs`, one generator seeded once for the whole
run, sizes in the order given), each policy is rolled out symbolically on the lifted world
model (:func:`csql_sim.core.policies.relational_rollout.rollout_relational`) and its plan compared
with the exact optimum (:func:`csql_sim.core.measure.optimum.optimal_length`, the four operators:
a pick and a put are two steps). Printed as a markdown table, one row per n and policy:
solved %, optimal % (of all pairs), the mean of length / optimum over solved pairs, and
the policy's wall time; the optimum's time is reported per n.

Policies, on the same pairs: ``lq-cs``, the lifted Q-classifiers learned on five blocks by
``csql-sim train-lifted`` (the rule file given, by default the shipped
``assets/rules/lifted.json``); ``gn1`` and ``gn2``, the hand-written baselines
(:mod:`csql_sim.core.policies.gn1`, :mod:`csql_sim.core.policies.gn2`); and the ``hand ordering``
over the same atoms as the rules, ``cover`` included (:mod:`csql_sim.core.policies.hand_ordering`).
These pairs (seed 0) are tuning tasks (:mod:`csql_sim.core.model.task_split`).
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.gn2 import Gn2Policy
from csql_sim.core.policies.hand_ordering import hand_ordering
from csql_sim.core.policies.lifted_policy import load_lifted_policy
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.state_count import sample_pairs


def policies(rules: str) -> dict:
    """The policies measured, by name."""
    return {"lq-cs": load_lifted_policy(rules), "gn1": Gn1Policy(), "gn2": Gn2Policy(),
            "hand ordering": hand_ordering()}


def measure(n: int, k: int, rng: np.random.Generator, rules: str) -> tuple[list[str], float]:
    """The table rows for n blocks (one per policy) and the optimum's wall time."""
    pairs = sample_pairs(n, k, rng)
    t0 = time.perf_counter()
    optima = []
    for i, (start, goal) in enumerate(pairs):
        optima.append(optimal_length(start, goal))
        if (i + 1) % 100 == 0:
            print(f"\rn = {n}: optimum {i + 1}/{k}", end="", file=sys.stderr)
    print(file=sys.stderr)
    optimum_seconds = time.perf_counter() - t0
    rows = []
    for name, policy in policies(rules).items():
        t0 = time.perf_counter()
        runs = [rollout_relational(policy, start, goal) for start, goal in pairs]
        seconds = time.perf_counter() - t0
        solved = [(r.length, o) for r, o in zip(runs, optima, strict=True) if r.reached]
        optimal = sum(length == o for length, o in solved)
        ratio = float(np.mean([length / o for length, o in solved])) if solved else float("nan")
        rows.append(f"| {n} | {name} | {k} | {100 * len(solved) / k:.1f}% | {100 * optimal / k:.1f}% | "
                    f"{ratio:.4f} | {seconds:.1f} |")
    return rows, optimum_seconds


def main(argv: list[str] | None = None) -> int:
    """Parse the options, measure every size, print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=1000, help="random pairs per n (default 1000)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the one generator (default 0)")
    parser.add_argument("--sizes", default="6,7,8,10,15,20,26", help="numbers of blocks (default 6,7,8,10,15,20,26)")
    parser.add_argument("--rules", default="assets/rules/lifted.json", help="lifted Q-classifier file (default "
                        "assets/rules/lifted.json)")
    args = parser.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",")]
    if args.pairs < 1 or any(not 2 <= n <= 26 for n in sizes):
        parser.error("--pairs must be positive and every size 2..26")
    rng = np.random.default_rng(args.seed)
    print("| n | policy | pairs | solved | optimal | mean length / optimum | policy wall s |")
    print("|---|---|---|---|---|---|---|", flush=True)
    timing = []
    for n in sizes:
        rows, seconds = measure(n, args.pairs, rng, args.rules)
        print("\n".join(rows), flush=True)
        timing.append(f"n = {n}: exact optimum of {args.pairs} pairs in {seconds:.1f} s")
    print("\n".join(["", *timing]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
