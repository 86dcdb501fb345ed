"""Held-out tall towers of hundreds of blocks: GN1, GN2, the hand ordering and the shipped rules against GN2.

Regenerates docs/results/large_problems.md, the table of held-out tall towers of 200 and 500
blocks (its rows in docs/large_heldout.jsonl)::

    python benchmarks/large_heldout.py --out docs/large_heldout.jsonl [--sizes 200,500] [--towers 10]
    python benchmarks/large_heldout.py --out docs/large_heldout.jsonl --report

Tasks: **held-out** (:mod:`csql_sim.core.model.task_split`): ``--towers`` tall-tower tasks per n
of ``--sizes``, drawn size after size from the held-out tall-tower seed (these sizes were never
drawn from it before, and no design choice looked at them). Their optima are not proven here,
so each planner's total length is reported against GN2's and against the lower bound (twice
the misplaced blocks: the ratio to it is an upper bound on the ratio to the optimum).

Planners: ``gn1``, ``gn2`` (the named baselines), the ``hand ordering`` (six ranks over the
given atoms, ``cover`` included) and the shipped lifted rules (``--rules builtin``,
``assets/rules/lifted.json``: learned; their plans come from their classifiers). One JSON line
per (planner, n), written as it is done: a stopped run resumes.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from csql_sim.core.measure.bounds import lower_bound
from csql_sim.core.model import task_split
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.gn2 import Gn2Policy
from csql_sim.core.policies.hand_ordering import hand_ordering
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.policies.relational_rollout import rollout_relational

SHIPPED = Path(__file__).resolve().parents[1] / "assets" / "rules" / "lifted.json"
PLANNERS = {"gn1": Gn1Policy, "gn2": Gn2Policy, "hand ordering": hand_ordering,
            "shipped lifted.json": lambda: load_policy(SHIPPED)}


def run_all(out: Path, sizes: list[int], count: int) -> None:
    """Plan every task with every planner not yet in ``out``."""
    rows = [json.loads(x) for x in out.read_text().splitlines()] if out.exists() else []
    done = {(r["planner"], r["n"]) for r in rows if r["tasks"] == count}
    tasks = task_split.held_out_towers(tuple(sizes), count)
    for n, pairs in tasks.items():
        bound = [lower_bound(s, g) for s, g in pairs]
        for name, make in PLANNERS.items():
            if (name, n) in done:
                continue
            t0 = time.process_time()
            runs = [rollout_relational(make(), s, g) for s, g in pairs]
            row = {"planner": name, "n": n, "tasks": count, "solved": sum(r.reached for r in runs),
                   "lengths": [r.length if r.reached else None for r in runs], "lower_bounds": bound,
                   "cpu_s_per_task": round((time.process_time() - t0) / count, 2)}
            with out.open("a") as f:
                f.write(json.dumps(row) + "\n")
            print(f"{name} n={n}: {row['solved']}/{count}, {row['cpu_s_per_task']} s per task", file=sys.stderr)


def report(out: Path) -> None:
    """Markdown: per n and planner, solved, total length, / GN2, / lower bound."""
    rows = [json.loads(x) for x in out.read_text().splitlines()]
    print("| n | planner | tasks | solved | total length | / GN2 | / (2 x misplaced) | CPU s per task |")
    print("|---|---|---|---|---|---|---|---|")
    for n in sorted({r["n"] for r in rows}):
        here = [r for r in rows if r["n"] == n]
        gn2 = next(r for r in here if r["planner"] == "gn2")
        for r in here:
            solved = [i for i, x in enumerate(r["lengths"]) if x is not None and gn2["lengths"][i] is not None]
            total = sum(r["lengths"][i] for i in solved)
            vs_gn2 = total / max(1, sum(gn2["lengths"][i] for i in solved))
            vs_bound = total / max(1, sum(r["lower_bounds"][i] for i in solved))
            print(f"| {n} | {r['planner']} | {r['tasks']} | {r['solved']} | {total:,} | {vs_gn2:.3f} | "
                  f"{vs_bound:.3f} | {r['cpu_s_per_task']} |")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="JSON lines, appended (resumes)")
    parser.add_argument("--report", action="store_true", help="print the table of --out and stop")
    parser.add_argument("--sizes", type=lambda t: [int(x) for x in t.split(",")], default=[200, 500])
    parser.add_argument("--towers", type=int, default=10)
    args = parser.parse_args(argv)
    out = Path(args.out)
    if args.report:
        if not out.exists():
            print(f"large_heldout: {out} does not exist", file=sys.stderr)
            return 2
        report(out)
        return 0
    run_all(out, args.sizes, args.towers)
    return 0


if __name__ == "__main__":
    sys.exit(main())
