"""The headline figures on tuning tasks and on held-out tasks, side by side, against the exact optimum.

Regenerates docs/results/lifted.md, the table of held-out tasks (its rows in docs/heldout.jsonl).

    python benchmarks/lifted_heldout.py --out docs/heldout.jsonl [--given-seeds 0-9] [--committee-seeds 0]
                                        [--pairs 100] [--pair-sizes 10,20,26] [--towers 10]
                                        [--tower-sizes 25,50,100] [--optimum-budget 20]
    python benchmarks/lifted_heldout.py --out docs/heldout.jsonl --report

Tasks (:mod:`csql_sim.core.model.task_split`): the **tuning** tasks are the first ``--pairs`` of
the benchmark's pairs (seed 0) at each n of ``--pair-sizes`` and ``--towers`` tall-tower tasks
per n of ``--tower-sizes`` drawn size after size from seed 0 (the feature table's); the
**held-out** tasks are as many uniform pairs and tall towers from the held-out seeds, which no
design choice looked at. Each task's optimum: the exact one for pairs
(:func:`~csql_sim.core.measure.optimum.optimal_length`), the implicit-hitting-set optimum for
tall towers (``--optimum-budget`` seconds each, the ``bench`` extra), narrowed by the shortest
plan measured; where it is not proven its lower bound stands in and the row says so.

Policies: the named baselines ``gn1`` and ``gn2``, the ``hand ordering`` (six ranks over the
given atoms, ``cover`` included) and ``hand-without-cover``; the shipped rules
(``assets/rules/lifted.json``); the given-atom learner (``train-lifted`` defaults) for every
seed of ``--given-seeds``; the move-formulation committee of generated features
(``train-lifted --features generated --domain move``, three members) for every seed of
``--committee-seeds``. Each learned file's agreement with the hand ordering
(:func:`csql_sim.core.policies.agreement.agreement`) is recorded. Learned figures come from
trials and the learner's sweeps through its world model; none from search.

One JSON line per (policy, seed, task set, n), written as it is done: a stopped run resumes.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from csql_sim.core.measure.bounds import hitting_set_optimum
from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model import task_split
from csql_sim.core.policies.agreement import agreement
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.gn2 import Gn2Policy
from csql_sim.core.policies.hand_ordering import hand_ordering, hand_ordering_without_cover
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.learners.lifted import LiftedParams, train_committee, train_lifted

SHIPPED = Path(__file__).resolve().parents[1] / "assets" / "rules" / "lifted.json"


def task_sets(args: argparse.Namespace) -> dict[tuple[str, str, int], list]:
    """``(tuning|held-out, pairs|tall, n) -> tasks``."""
    out = {}
    for split, pairs, towers in (("tuning", task_split.tuning_pairs, task_split.tuning_towers),
                                 ("held-out", task_split.held_out_pairs, task_split.held_out_towers)):
        out.update({(split, "pairs", n): t for n, t in pairs(tuple(args.pair_sizes), args.pairs).items()})
        out.update({(split, "tall", n): t for n, t in towers(tuple(args.tower_sizes), args.towers).items()})
    return out


def optima(tasks: dict, budget: float, cache: Path) -> dict[tuple, list[tuple[int, bool]]]:
    """Each task's optimum (lower bound, proven), kept in ``cache`` (a JSON file) across runs."""
    known = json.loads(cache.read_text()) if cache.exists() else {}
    out = {}
    for key, rows in tasks.items():
        name = "/".join(map(str, key)) + f"/{len(rows)}"
        if name not in known:
            t0 = time.perf_counter()
            found = []
            for s, g in rows:
                if key[1] == "pairs":
                    found.append((optimal_length(s, g), True))
                else:
                    upper = min(rollout_relational(p, s, g).length for p in (Gn2Policy(), hand_ordering()))
                    bound = hitting_set_optimum(s, g, budget, upper=upper)
                    found.append((bound.lower, bound.proven))
            known[name] = found
            cache.write_text(json.dumps(known))
            print(f"optimum {name}: {time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)
        out[key] = [tuple(x) for x in known[name]]
    return out


def measure(policy, rows: list, best: list[tuple[int, bool]]) -> dict:  # noqa: ANN001 - any policy
    """Solved and optimal % and total length / total optimum over the solved tasks."""
    t0 = time.process_time()
    runs = [rollout_relational(policy, s, g) for s, g in rows]
    solved = [(r.length, o) for r, (o, _) in zip(runs, best, strict=True) if r.reached]
    return {"tasks": len(rows), "solved": 100 * len(solved) / len(rows),
            "optimal": 100 * sum(length == o for length, o in solved) / len(rows),
            "ratio": sum(length for length, _ in solved) / max(1, sum(o for _, o in solved)),
            "proven": sum(p for _, p in best), "cpu_s": round(time.process_time() - t0, 2)}


def policies(args: argparse.Namespace, done: set):  # noqa: ANN201 - yields (name, seed, policy, extra)
    """Every policy not in ``done`` (``(name, seed)``), trained when learned (one at a time)."""
    yield "gn1", None, Gn1Policy, {}
    yield "gn2", None, Gn2Policy, {}
    yield "hand ordering", None, hand_ordering, {}
    yield "hand-without-cover", None, hand_ordering_without_cover, {}
    if ("shipped lifted.json", 0) not in done:
        shipped = load_policy(SHIPPED)
        yield "shipped lifted.json", 0, lambda: load_policy(SHIPPED), {"agreement": agreement(shipped).as_dict()}
    for seed in args.given_seeds:
        if ("given atoms", seed) in done:
            continue
        run = train_lifted(LiftedParams(), np.random.default_rng(seed))
        extra = {"training_s": round(run.seconds, 1), "classifiers": len(run.classifiers),
                 "agreement": agreement(run.policy()).as_dict()}
        yield "given atoms", seed, run.policy, extra
    for seed in args.committee_seeds:
        if ("committee-move", seed) in done:
            continue
        params = LiftedParams(features="generated", domain="move")
        run = train_committee(params, np.random.default_rng(seed), 3)
        extra = {"training_s": round(run.seconds, 1), "agreement": agreement(run.policy()).as_dict()}
        yield "committee-move", seed, run.policy, extra


def run_all(args: argparse.Namespace) -> None:
    """Measure every policy on every task set not yet in ``--out``."""
    out = Path(args.out)
    done = set()
    if out.exists():
        done = {(r["policy"], r["seed"]) for r in map(json.loads, out.read_text().splitlines())}
    tasks = task_sets(args)
    best = optima(tasks, args.optimum_budget, out.with_suffix(".optima.json"))
    for name, seed, make, extra in policies(args, done):
        if (name, seed) in done:
            continue
        print(f"{name} seed {seed}", file=sys.stderr, flush=True)
        lines = []
        for (split, kind, n), rows in tasks.items():
            row = {"policy": name, "seed": seed, "split": split, "set": kind, "n": n,
                   **measure(make(), rows, best[(split, kind, n)]), **extra}
            lines.append(json.dumps(row))
        with out.open("a") as f:
            f.write("\n".join(lines) + "\n")


def report(path: str) -> None:
    """Markdown: per task set and policy, tuning and held-out side by side (learned: min / median / max)."""
    rows = [json.loads(x) for x in Path(path).read_text().splitlines()]
    print("| tasks | policy | agreement | tuning: optimal % | tuning: cost / optimum | held-out: optimal % "
          "| held-out: cost / optimum |")
    print("|---|---|---|---|---|---|---|")
    for kind, n in dict.fromkeys((r["set"], r["n"]) for r in rows):
        proven = {s: min(r["proven"] for r in rows if (r["set"], r["n"], r["split"]) == (kind, n, s))
                  for s in ("tuning", "held-out")}
        count = next(r["tasks"] for r in rows if (r["set"], r["n"]) == (kind, n))
        label = f"{kind} n = {n}, {count} each" + ("" if min(proven.values()) == count else
                                                    f" (proven: {proven['tuning']} / {proven['held-out']})")
        for name in dict.fromkeys(r["policy"] for r in rows):
            cells = []
            for split in ("tuning", "held-out"):
                found = [r for r in rows if (r["policy"], r["set"], r["n"], r["split"]) == (name, kind, n, split)]
                cells += [spread([r["optimal"] for r in found], 1), spread([r["ratio"] for r in found], 3)]
            seeds = sorted({r["seed"] for r in rows if r["policy"] == name and r["seed"] is not None})
            who = name + (f", seeds {seeds[0]}-{seeds[-1]}" if len(seeds) > 1 else
                          f", seed {seeds[0]}" if seeds and name != "shipped lifted.json" else "")
            agreed = [100 * r["agreement"]["share"] for r in rows if r["policy"] == name and "agreement" in r]
            share = "the reference" if name == "hand ordering" else spread(agreed, 1) + "%" if agreed else "-"
            print(f"| {label} | {who} | {share} | {' | '.join(cells)} |")


def spread(values: list[float], digits: int) -> str:
    """One value, or min / median / max."""
    if not values:
        return "-"
    if min(values) == max(values):
        return f"{values[0]:.{digits}f}"
    return " / ".join(f"{v:.{digits}f}" for v in (min(values), statistics.median(values), max(values)))


def seeds_arg(text: str) -> list[int]:
    """``0-9`` or ``0,3`` or empty."""
    if not text:
        return []
    a, _, b = text.partition("-")
    return list(range(int(a), int(b) + 1)) if b else [int(x) for x in text.split(",")]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="JSON lines, appended (resumes)")
    parser.add_argument("--report", action="store_true", help="print the table of --out and stop")
    parser.add_argument("--given-seeds", type=seeds_arg, default=seeds_arg("0-9"))
    parser.add_argument("--committee-seeds", type=seeds_arg, default=[])
    parser.add_argument("--pairs", type=int, default=100)
    parser.add_argument("--pair-sizes", type=lambda t: [int(x) for x in t.split(",")], default=[10, 20, 26])
    parser.add_argument("--towers", type=int, default=10)
    parser.add_argument("--tower-sizes", type=lambda t: [int(x) for x in t.split(",")], default=[25, 50, 100])
    parser.add_argument("--optimum-budget", type=float, default=20.0)
    args = parser.parse_args(argv)
    if args.report:
        report(args.out)
        return 0
    run_all(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
