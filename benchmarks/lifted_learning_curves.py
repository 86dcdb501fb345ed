"""LQ-CS learning curves: optimal % at n = 10 and 20 against training trials, several seeds, one run each.

Regenerates docs/results/lifted.md, the learning curves.

    python benchmarks/lifted_learning_curves.py [--seeds 0-4] [--checkpoints 10,30,100,300,1000,3000,10000,30000]
                                    [--pairs 1000] [--sizes 10,20] [--pairs-seed 0]
                                    [--json curves.json] [--png curves.png]
    python benchmarks/lifted_learning_curves.py --merge a.json b.json --json curves.json [--png curves.png]

For every seed, one training run with the learner's defaults (``trials`` set to the last
checkpoint) from ``np.random.default_rng(seed)``; at every checkpoint the classifiers of that
moment (``train_lifted``'s ``at_checkpoint``) plan the fixed pairs of every n of ``--sizes``
(``--pairs`` per n, drawn in turn by one generator seeded ``--pairs-seed``), and solved and
optimal % are recorded against the exact optimum (a yardstick). Results go to ``--json`` and,
with ``--png``, a plot: one line per seed, one panel per n. ``--merge`` joins the seeds of runs
made side by side (same pairs and checkpoints) into one file and plot.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np
from lifted_learning_seeds import score  # the script beside this one

from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.policies.lifted_policy import LiftedPolicy
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.learners.lifted.params import LiftedParams
from csql_sim.learners.lifted.ql import train_lifted


def seeds_of(text: str) -> list[int]:
    """A range a-b or a comma list."""
    a, _, b = text.partition("-")
    return list(range(int(a), int(b) + 1)) if b else [int(x) for x in text.split(",")]


def curve(seed: int, checkpoints: list[int], data: dict) -> dict:
    """One seed's run: per checkpoint and n, solved and optimal %; and the training seconds."""
    points: dict[str, dict[str, list[float]]] = {}

    def measure(k: int, classifiers: tuple) -> None:
        policy = LiftedPolicy(classifiers)
        points[str(k)] = {str(n): list(score(policy, *data[n])) for n in data}
        cells = " ".join(f"n={n} {v[0]:.1f}/{v[1]:.1f}" for n, v in points[str(k)].items())
        print(f"seed {seed} trials {k}: {cells}", file=sys.stderr, flush=True)

    t0 = time.perf_counter()
    run = train_lifted(LiftedParams(trials=max(checkpoints)), np.random.default_rng(seed),
                       checkpoints=set(checkpoints), at_checkpoint=measure)
    return {"points": points, "training_seconds": run.seconds, "wall_seconds": time.perf_counter() - t0}


def plot(result: dict, path: str) -> None:
    """One panel per n: optimal % against trials (log scale), one line per seed."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sizes = result["sizes"]
    fig, axes = plt.subplots(1, len(sizes), figsize=(5 * len(sizes), 3.6), squeeze=False)
    for ax, n in zip(axes[0], sizes, strict=True):
        for seed, run in result["seeds"].items():
            ks = sorted(run["points"], key=int)
            ax.plot([int(k) for k in ks], [run["points"][k][str(n)][1] for k in ks], marker="o", label=f"seed {seed}")
        ax.axvline(result["default_trials"], color="grey", linestyle=":", label="default trials")
        ax.set_xscale("log")
        ax.set_xlabel("training trials")
        ax.set_ylabel("optimal %")
        ax.set_title(f"n = {n}, {result['pairs']} pairs")
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def merge(paths: list[str], out: str, png: str | None) -> int:
    """Join the seeds of several results files made on the same pairs and checkpoints."""
    docs = [json.load(open(p)) for p in paths]
    keys = ("sizes", "pairs", "pairs_seed", "checkpoints", "default_trials")
    if any(d[k] != docs[0][k] for d in docs for k in keys):
        print(f"lifted_curves: {', '.join(paths)} were not made on the same pairs and checkpoints", file=sys.stderr)
        return 2
    result = {**{k: docs[0][k] for k in keys}, "seeds": {}}
    for d in docs:
        result["seeds"].update(d["seeds"])
    result["seeds"] = dict(sorted(result["seeds"].items(), key=lambda kv: int(kv[0])))
    with open(out, "w") as f:
        json.dump(result, f, indent=1)
    if png:
        plot(result, png)
    return 0


def main(argv: list[str] | None = None) -> int:
    """Run every seed, write the JSON and the plot."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0-4", help="seeds, a range a-b or a comma list (default 0-4)")
    parser.add_argument("--checkpoints", default="10,30,100,300,1000,3000,10000,30000",
                        help="trial counts measured (default 10,30,100,300,1000,3000,10000,30000)")
    parser.add_argument("--pairs", type=int, default=1000, help="pairs per n (default 1000)")
    parser.add_argument("--sizes", default="10,20", help="numbers of blocks (default 10,20)")
    parser.add_argument("--pairs-seed", type=int, default=0, help="seed of the pairs' generator (default 0)")
    parser.add_argument("--json", default="curves.json", help="results file (default curves.json)")
    parser.add_argument("--png", help="plot file (default: none)")
    parser.add_argument("--merge", nargs="+", metavar="JSON", help="join these results files instead of running")
    args = parser.parse_args(argv)
    if args.merge:
        return merge(args.merge, args.json, args.png)
    checkpoints = sorted({int(x) for x in args.checkpoints.split(",")})
    sizes = [int(x) for x in args.sizes.split(",")]
    rng = np.random.default_rng(args.pairs_seed)
    data = {}
    for n in sizes:
        pairs = sample_pairs(n, args.pairs, rng)
        data[n] = (pairs, [optimal_length(s, g) for s, g in pairs])
    result = {"sizes": sizes, "pairs": args.pairs, "pairs_seed": args.pairs_seed, "checkpoints": checkpoints,
              "default_trials": LiftedParams().trials, "seeds": {}}
    for seed in seeds_of(args.seeds):
        result["seeds"][str(seed)] = curve(seed, checkpoints, data)
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)
    if args.png:
        plot(result, args.png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
