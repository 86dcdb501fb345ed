"""Sweep the bucket-brigade constants against the paper's statements about Figure 7.

Regenerates docs/results/figure7.md, the bucket-brigade sweep.

For every combination of ``--bid``, ``--tax``, ``--s0`` and ``--payoff`` this runs
CS-BB-BZ and CS-BB-RW for ``--cycles`` x ``--trials`` (LT-QL and CS-QL once, as they do
not depend on these constants), checks :func:`csql_sim.jobs.figure7_statements.evaluate`, and
writes one CSV row per combination plus a plot of the levers against the statements.

    python benchmarks/learning_bucket_brigade.py --cycles 20 --out docs/sweep_bucket_brigade
"""

from __future__ import annotations

import argparse
import csv
import itertools
import os
import time
from pathlib import Path

from csql_sim.jobs.experiment import ExperimentResult, run_experiment
from csql_sim.jobs.figure7_statements import early_value, end_steps, end_value, evaluate, first_reach
from csql_sim.learners.paper.params import BucketBrigadeParams


def floats(text: str) -> list[float]:
    return [float(x) for x in text.split(",") if x.strip()]


def sweep(args: argparse.Namespace) -> list[dict]:
    common = dict(cycles=args.cycles, trials=args.trials, seed=args.seed, workers=args.workers)
    reference = run_experiment(["lt-ql", "cs-ql"], **common)
    rows = []
    for bid, tax, s0, payoff in itertools.product(args.bid, args.tax, args.s0, args.payoff):
        began = time.perf_counter()
        p = BucketBrigadeParams(bid=bid, tax=tax, s0=s0, payoff=payoff)
        bb = run_experiment(["cs-bb-bz", "cs-bb-rw"], params={"cs-bb-bz": p, "cs-bb-rw": p}, **common)
        result = ExperimentResult(reference.methods + bb.methods, args.cycles, args.trials, args.seed, bb.optimal)
        statements = evaluate(result)
        by = {r.method: r for r in result.methods}
        rw, bz = by["cs-bb-rw"], by["cs-bb-bz"]
        row = {
            "bid": bid, "tax": tax, "s0": s0, "payoff": payoff,
            "bz_first": first_reach(bz, result.optimal), "rw_first": first_reach(rw, result.optimal),
            "rw_best": round(float(rw.steps.mean(axis=0).min()), 3), "rw_end": round(end_steps(rw), 2),
            "bz_end": round(end_steps(bz), 2),
            "bz_early": round(early_value(bz), 3), "rw_early": round(early_value(rw), 3),
            "csql_early": round(early_value(by["cs-ql"]), 3),
            "rw_value_peak": round(float(rw.values.mean(axis=0).max()), 3), "rw_value_end": round(end_value(rw), 3),
        }
        row.update({s.name: int(s.holds) for s in statements})
        row["holds"] = sum(s.holds for s in statements)
        row["of"] = len(statements)
        rows.append(row)
        print(f"{row} ({time.perf_counter() - began:.0f} s)", flush=True)
    return rows


def plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    taxes = sorted({r["tax"] for r in rows})
    fig = Figure(figsize=(12, 3.6 * len(taxes)))
    axes = fig.subplots(len(taxes), 3, squeeze=False)
    for row_axes, tax in zip(axes, taxes, strict=True):
        sel = [r for r in rows if r["tax"] == tax]
        for bid in sorted({r["bid"] for r in sel}):
            line = sorted((r for r in sel if r["bid"] == bid), key=lambda r: r["s0"])
            s0 = [r["s0"] for r in line]
            row_axes[0].plot(s0, [r["rw_best"] for r in line], "o-", label=f"bid {bid:g}")
            row_axes[1].plot(s0, [r["rw_end"] for r in line], "o-", label=f"bid {bid:g}")
            row_axes[2].plot(s0, [min(r["bz_early"], r["rw_early"]) - r["csql_early"] for r in line], "o-",
                             label=f"bid {bid:g}")
        row_axes[0].axhline(8, color="grey", lw=0.8)
        row_axes[0].set_title(f"tax {tax:g}: CS-BB-RW best mean steps (optimum 8)", fontsize=9)
        row_axes[1].axhspan(56.25, 93.75, color="grey", alpha=0.2)
        row_axes[1].set_title(f"tax {tax:g}: CS-BB-RW end steps (paper ~75)", fontsize=9)
        row_axes[2].axhline(0, color="grey", lw=0.8)
        row_axes[2].set_title(f"tax {tax:g}: (b) min(BZ, RW) - CS-QL value, trials 50-625", fontsize=9)
        ticks = sorted({r["s0"] for r in sel})
        for ax in row_axes:
            ax.set_xscale("log")
            ax.set_xticks(ticks, [f"{t:g}" for t in ticks])
            ax.minorticks_off()
            ax.set_xlabel("s0 (initial strength)")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bid", type=floats, default=floats("0.2,0.5,0.8"))
    ap.add_argument("--tax", type=floats, default=floats("0"))
    ap.add_argument("--s0", type=floats, default=floats("0.001,0.003,0.01,0.03"))
    ap.add_argument("--payoff", type=floats, default=floats("1"))
    ap.add_argument("--cycles", type=int, default=20)
    ap.add_argument("--trials", type=int, default=2500)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--workers", type=int, default=os.cpu_count())
    ap.add_argument("--out", default="sweep_bucket_brigade", help="writes OUT.csv and OUT.png")
    ap.add_argument("--replot", action="store_true", help="redraw OUT.png from OUT.csv without running")
    args = ap.parse_args()
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    if args.replot:
        with open(out.with_suffix(".csv"), newline="") as f:
            plot([{k: float(v) if v else None for k, v in row.items()} for row in csv.DictReader(f)],
                 out.with_suffix(".png"))
        return
    rows = sweep(args)
    with open(out.with_suffix(".csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plot(rows, out.with_suffix(".png"))
    print(f"wrote {out.with_suffix('.csv')} and {out.with_suffix('.png')}")


if __name__ == "__main__":
    main()
