"""The table and plot of ``benchmarks/large_problems.py`` from its JSON-lines files.

Regenerates docs/results/large_problems.md, the table and docs/large_problems_time.png.

    python benchmarks/large_problems_report.py DIR [--png docs/large_problems_time.png]

Reads DIR/plans.jsonl and DIR/optimum.jsonl, writes DIR/table.md and the PNG (default
DIR/time_per_task.png), and prints the table.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
from pathlib import Path

import numpy as np

PLANNERS = {"rules": "lifted rules", "gn1": "GN1", "gn2": "GN2", "fd": "Fast Downward"}


def _rows(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()] if path.exists() else []


def merged_optima(path: Path) -> dict[str, dict]:
    """Per task, the best bounds of all its rows (a task measured again with more time keeps the tighter)."""
    out: dict[str, dict] = {}
    for row in _rows(path):
        old = out.get(row["task"])
        if old is not None:
            row = {**row, "lower": max(row["lower"], old["lower"]), "upper": min(row["upper"], old["upper"])}
            row["proven"] = row["lower"] == row["upper"]
        out[row["task"]] = row
    return out


def reference(opt: dict) -> tuple[int, bool]:
    """A task's yardstick: its optimum when proven, else its best lower bound; and whether proven."""
    return (opt["lower"], True) if opt["proven"] else (max(opt["lower"], opt["lower_bound"]), False)


def slope(points: list[tuple[int, float]]) -> float | None:
    """The least-squares slope of log(time) against log(n), or None with fewer than two sizes."""
    if len({n for n, _ in points}) < 2:
        return None
    x, y = np.log([n for n, _ in points]), np.log([max(t, 1e-6) for _, t in points])
    return float(np.polyfit(x, y, 1)[0])


def _ratios(measured: list[tuple[int, int, bool]]) -> tuple[str, str, str]:
    """Cost / yardstick over all measured tasks, over the proven ones, and how many are proven."""
    if not measured:
        return "-", "-", "-"
    exact = sum(p for _, _, p in measured)
    ratio = f"{sum(c for c, _, _ in measured) / sum(r for _, r, _ in measured):.3f}"
    ratio += "" if exact == len(measured) else " (bound)"
    proven = f"{exact} proven" + ("" if exact == len(measured) else f", {len(measured) - exact} bounded")
    on_proven = "-"
    if exact:
        on_proven = f"{sum(c for c, _, p in measured if p) / sum(r for _, r, p in measured if p):.3f} ({exact})"
    return ratio, on_proven, proven


def table(out: Path) -> tuple[list[str], dict[str, list[tuple[int, float]]]]:
    """The markdown lines and, per planner, (n, median seconds per task: CPU, or wall for Fast Downward)."""
    plans, optima = _rows(out / "plans.jsonl"), merged_optima(out / "optimum.jsonl")
    lines = ["| n | planner | tasks | solved | total cost | cost / optimum | on proven tasks | optimum "
             "| time per task (CPU s) | wall s |", "|---|---|---|---|---|---|---|---|---|---|"]
    times: dict[str, list[tuple[int, float]]] = {}
    for n in sorted({r["n"] for r in plans}):
        for key, label in PLANNERS.items():
            rows = [r for r in plans if r["n"] == n and r["planner"] == key]
            if not rows:
                continue
            solved = [r for r in rows if r["solved"]]
            cpu = statistics.median(r["cpu_s"] for r in rows)
            wall = statistics.median(r["wall_s"] for r in rows)
            times.setdefault(key, []).append((n, wall if key == "fd" else cpu))  # a killed planner has no CPU
            measured = [(r["cost"], *reference(optima[r["task"]])) for r in solved if r["task"] in optima]
            ratio, on_proven, proven = _ratios(measured)
            cost = sum(r["cost"] for r in solved)
            lines.append(f"| {n} | {label} | {len(rows)} | {len(solved)} | {cost:,} | {ratio} | {on_proven} | "
                         f"{proven} | {cpu:.2f} | {wall:.2f} |")
    return lines, times


def plot(times: dict[str, list[tuple[int, float]]], png: Path) -> dict[str, float | None]:
    """Time per task against n on log-log axes, with each planner's fitted slope; returns the slopes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    slopes = {}
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for key, points in times.items():
        slopes[key] = slope(points)
        label = PLANNERS[key] + (", wall s with timeouts" if key == "fd" else "")
        label += "" if slopes[key] is None else f" (slope {slopes[key]:.2f})"
        ax.plot([n for n, _ in points], [t for _, t in points], marker="o", label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("blocks (tall-tower tasks)")
    ax.set_ylabel("time per task, s (median)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="lower right", fontsize="small")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return slopes


def report(out: Path, png: Path | None = None) -> str:
    """Write DIR/table.md and the plot; return the table's text with the slopes."""
    lines, times = table(out)
    slopes = plot(times, png or out / "time_per_task.png")
    lines += ["", "Fitted log-log slope of time per task against n: " + ", ".join(
        f"{PLANNERS[k]} {s:.2f}" if s is not None and math.isfinite(s) else f"{PLANNERS[k]} -"
        for k, s in slopes.items())]
    text = "\n".join(lines) + "\n"
    (out / "table.md").write_text(text)
    return text


def main(argv: list[str] | None = None) -> int:
    """Parse the options and write the report."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", help="the benchmark's --out folder")
    parser.add_argument("--png", default=None, help="where to draw the plot (default DIR/time_per_task.png)")
    args = parser.parse_args(argv)
    print(report(Path(args.out), None if args.png is None else Path(args.png)), end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
