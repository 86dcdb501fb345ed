"""The generated learner with and without its tie-break over generated features, on tuning and held-out pairs.

Regenerates docs/results/features.md, its section "A tie-break over generated features".

    python benchmarks/features_tie_break.py --seeds 0-2 --early 0,0.02 --split tuning [--use 30] [--out tie.jsonl]
    python benchmarks/features_tie_break.py --seeds 0-2 --early 0.02 --split held-out [--use 30] [--out tie.jsonl]

Each (seed, early) trains one population over generated features in the move formulation
(``LiftedParams(features="generated", domain="move", early=...)``, the other parameters their
defaults) from ``np.random.default_rng(seed)``, and plans ``--use`` pairs at n = 10 and 20: the
first of the benchmark's pairs (``--split tuning``, :func:`~csql_sim.core.model.task_split.tuning_pairs`)
or held-out ones (``--split held-out``, :func:`~csql_sim.core.model.task_split.held_out_pairs`),
against the exact optimum. A run with a fitted potential is measured twice: with the policy's
tie literal (its default) and without it. GN2 is measured on the same pairs. Figures come from
trials and the learner's sweeps through its world model; none from search. One JSON line per
row, appended to ``--out``.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from features_table import measure  # noqa: E402 - the feature table's measure, as a sibling script

from csql_sim.core.measure.optimum import optimal_length  # noqa: E402
from csql_sim.core.model import task_split  # noqa: E402
from csql_sim.core.policies.gn2 import Gn2Policy  # noqa: E402
from csql_sim.learners.lifted import LiftedParams, train_lifted  # noqa: E402


def pairs(split: str, use: int) -> dict[str, list[tuple]]:
    """The pairs at n = 10 and 20 of the split, with their exact optimum."""
    drawn = (task_split.tuning_pairs if split == "tuning" else task_split.held_out_pairs)((10, 20), use)
    return {f"n={n}": [(s, g, optimal_length(s, g), True) for s, g in rows] for n, rows in drawn.items()}


def summary(results: dict[str, dict]) -> dict[str, list[float]]:
    """Per label: optimal %, length / optimum, solved %."""
    return {k: [round(v["optimal"], 1), round(v["ratio"], 4), v["solved"]] for k, v in results.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0-2")
    parser.add_argument("--early", default="0,0.02")
    parser.add_argument("--split", choices=("tuning", "held-out"), default="tuning")
    parser.add_argument("--use", type=int, default=30)
    parser.add_argument("--trials", type=int, default=3000)
    parser.add_argument("--out", default="tie_break.jsonl")
    args = parser.parse_args()
    lo, _, hi = args.seeds.partition("-")
    seeds = range(int(lo), int(hi or lo) + 1)
    data = pairs(args.split, args.use)
    rows = [{"policy": "gn2", "split": args.split, "results": summary(measure(Gn2Policy(), data))}]
    for seed in seeds:
        for early in (float(e) for e in args.early.split(",")):
            params = LiftedParams(features="generated", domain="move", early=early, trials=args.trials)
            run = train_lifted(params, np.random.default_rng(seed))
            policy = run.policy()
            base = {"seed": seed, "early": early, "split": args.split, "training_seconds": round(run.seconds, 1),
                    "potential": run.features.get("potential"), "classifiers": len(run.classifiers)}
            rows.append({**base, "policy": "tie" if policy.tie else "plain",
                         "results": summary(measure(policy, data, hand=False))})
            if policy.tie is not None:
                policy.tie = None
                policy._match.clear()
                rows.append({**base, "policy": "plain", "results": summary(measure(policy, data, hand=False))})
    with open(args.out, "a") as f:
        for row in rows:
            f.write(json.dumps(row) + "\n")
            print(json.dumps(row))


if __name__ == "__main__":
    main()
