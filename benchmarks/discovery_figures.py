"""Transitions and failed attempts that rule discovery needs, over seeds and settings.

Regenerates docs/results/discovery.md, the table of transitions and failed attempts per setting.

Runs `discover` for each setting and seed and prints the median and maximum of the
transitions until the rule set was final, all transitions until the stop, failed attempts,
simulated and wall seconds, and how many runs induced all given rules string for string.

    python benchmarks/discovery_figures.py --seeds 10 --settings symbolic,pose,pose-perturb,camera --json out.json
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time

from csql_sim.discovery.explore import Exploration
from csql_sim.jobs.discover import discover

SETTINGS = {
    "symbolic": dict(world="symbolic", perception="pose", perturb=False),
    "symbolic-perturb": dict(world="symbolic", perception="pose", perturb=True),
    "pose": dict(world="physical", perception="pose", perturb=False),
    "pose-perturb": dict(world="physical", perception="pose", perturb=True),
    "camera": dict(world="physical", perception="camera", perturb=False),
}


def run(setting: str, seeds: range, n: int, cap: int) -> dict:
    rows = []
    for seed in seeds:
        began = time.perf_counter()
        r = discover(n, seed=seed, settings=Exploration(max_transitions=cap), **SETTINGS[setting])
        rows.append({"seed": seed, "final_after": r.last_change, "failed_to_final": r.failed_to_final,
                     "transitions": r.transitions, "failed": r.failed,
                     "restarts": r.restarts, "sim_seconds": round(r.sim_seconds, 1),
                     "wall_seconds": round(time.perf_counter() - began, 1), "equal": r.equal_to_given,
                     "rules": len(r.rules), "perturbations": len(r.events),
                     "disturbed": r.disturbed})
        print(setting, rows[-1], file=sys.stderr, flush=True)
    summary = {"setting": setting, "runs": len(rows), "all_36_equal": sum(x["equal"] for x in rows)}
    for key in ("final_after", "failed_to_final", "transitions", "failed", "disturbed", "sim_seconds",
                "wall_seconds"):
        values = [x[key] for x in rows]
        summary[key] = {"median": statistics.median(values), "max": max(values)}
    return {"summary": summary, "runs": rows}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--blocks", type=int, default=3)
    ap.add_argument("--transitions", type=int, default=20000)
    ap.add_argument("--settings", default="symbolic,symbolic-perturb,pose,pose-perturb,camera")
    ap.add_argument("--json")
    args = ap.parse_args()
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    out = [run(s, seeds, args.blocks, args.transitions) for s in args.settings.split(",")]
    for item in out:
        s = item["summary"]
        print(f"{s['setting']:<17} runs {s['runs']:>2}  all equal {s['all_36_equal']:>2}  "
              + "  ".join(f"{k} {s[k]['median']}/{s[k]['max']}"
                          for k in ("final_after", "failed_to_final", "transitions", "failed", "disturbed",
                                    "sim_seconds", "wall_seconds")))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=1)


if __name__ == "__main__":
    main()
