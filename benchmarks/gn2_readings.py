"""GN2's readings side by side on tuning tasks, against the figures of Slaney and Thiébaux's C code.

Regenerates docs/results/lifted.md, the table "GN2 against the authors' figures" (and the
figures in the docstring of ``csql_sim/core/policies/gn2.py``)::

    python benchmarks/gn2_readings.py [--optima docs/heldout.optima.json] [--ratio-towers 30]

Tasks: **tuning** only (:mod:`csql_sim.core.model.task_split`; the choice of reading was made
on them): the first 10 tall-tower tasks per n of 25, 50 and 100 (seed 0, the held-out
benchmark's) and the first 100 of the benchmark's pairs at n = 20, against their proven
optima (the cache ``benchmarks/lifted_heldout.py`` writes); and ``--ratio-towers`` tall towers
per n (seed 0) for GN2 / GN1, which needs no optimum. One figure per reading and task set:
total plan length / total optimum (or / GN1's total).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from csql_sim.core.model import task_split
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.gn2 import READING, READINGS, Gn2Policy
from csql_sim.core.policies.relational_rollout import rollout_relational

SIZES = (25, 50, 100)
AUTHORS = {"gn1 / opt": (1.037, 1.058, 1.127), "gn2 / opt": (1.000, 1.021, 1.060),
           "gn2 / gn1": (0.964, 0.965, 0.941), "pairs 20": 1.009}
"""The authors' C code: 10 tall towers per n of 25, 50, 100; uniform random problems at n = 20."""


def total(make, rows: list) -> int:  # noqa: ANN001 - any policy factory
    """The total plan length (every task must be solved)."""
    runs = [rollout_relational(make(), s, g) for s, g in rows]
    if not all(r.reached for r in runs):
        raise SystemExit("a task was not solved")
    return sum(r.length for r in runs)


def table(optima: dict, ratio_towers: int) -> list[str]:
    """Markdown rows: GN1 and every reading, then the authors' figures."""
    towers = task_split.tuning_towers(SIZES, 10)
    many = task_split.tuning_towers(SIZES, ratio_towers)
    pairs = task_split.tuning_pairs((20,), 100)[20]
    best = {n: sum(o for o, _ in optima[f"tuning/tall/{n}/10"]) for n in SIZES}
    best_pairs = sum(o for o, _ in optima["tuning/pairs/20/100"])
    gn1 = {n: total(Gn1Policy, many[n]) for n in SIZES}
    lines = ["| planner | " + " | ".join(f"/ opt, tall {n}" for n in SIZES) + " | "
             + " | ".join(f"/ GN1, tall {n} ({ratio_towers})" for n in SIZES) + " | / opt, pairs 20 |",
             "|---" * 8 + "|"]
    cells = [f"{total(Gn1Policy, towers[n]) / best[n]:.3f}" for n in SIZES] + ["1"] * 3
    lines.append(f"| GN1 | {' | '.join(cells)} | {total(Gn1Policy, pairs) / best_pairs:.3f} |")
    for name in READINGS:
        def make(name: str = name) -> Gn2Policy:
            return Gn2Policy(name)
        cells = [f"{total(make, towers[n]) / best[n]:.3f}" for n in SIZES]
        cells += [f"{total(make, many[n]) / gn1[n]:.3f}" for n in SIZES]
        label = f"GN2 `{name}`" + (" (adopted)" if name == READING else "")
        lines.append(f"| {label} | {' | '.join(cells)} | {total(make, pairs) / best_pairs:.3f} |")
        print(lines[-1], file=sys.stderr, flush=True)
    authors = [f"{x:.3f}" for x in AUTHORS["gn2 / opt"]] + [f"{x:.3f}" for x in AUTHORS["gn2 / gn1"]]
    theirs = " | ".join(f"{x:.3f}" for x in AUTHORS["gn1 / opt"])
    lines.append(f"| GN1, authors (10 per n) | {theirs} | - | - | - | - |")
    lines.append(f"| GN2, authors (10 per n) | {' | '.join(authors)} | {AUTHORS['pairs 20']:.3f} |")
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--optima", default="docs/heldout.optima.json", help="benchmarks/lifted_heldout.py's cache")
    parser.add_argument("--ratio-towers", type=int, default=30)
    args = parser.parse_args(argv)
    path = Path(args.optima)
    try:
        optima = json.loads(path.read_text())
        missing = [k for k in [f"tuning/tall/{n}/10" for n in SIZES] + ["tuning/pairs/20/100"] if k not in optima]
    except (OSError, ValueError) as err:
        print(f"gn2_readings: cannot read {path}: {err}", file=sys.stderr)
        return 2
    if missing:
        print(f"gn2_readings: {path} lacks {', '.join(missing)} (run benchmarks/lifted_heldout.py)", file=sys.stderr)
        return 2
    print("\n".join(table(optima, args.ratio_towers)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
