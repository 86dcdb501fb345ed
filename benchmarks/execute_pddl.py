"""Run 7..10-block PDDL tasks through ``execute``: an outside planner's plans, the lifted rules and GN1.

Regenerates docs/results/arm.md, the table of PDDL tasks executed on the arm.

    python benchmarks/execute_pddl.py OUTDIR [--named K] [--problems DIR --domain D]
        [--seed S] [--perception pose|camera] [--overwrite]

OUTDIR gets K generated tasks (``named-<k>.pddl``: 7..10 objects with names of every kind,
a start drawn uniformly, a partial goal of 2..n-1 ``on`` atoms of another uniform state),
the plan pyperplan finds for each task (greedy best-first search with the FF heuristic,
``<task>.pddl.soln``) and the report ``report.json``. ``--problems DIR`` adds every
``*.pddl`` problem of a folder (e.g. IPC 2000's ``probBLOCKS-7-0`` .. ``probBLOCKS-10-2``,
with their ``--domain``). Every task runs three times on the arm: the plan file, the
shipped lifted rules and GN1; a run counts as reached when the perceived final state
satisfies the goal's atoms. Needs pyperplan (``pip install pyperplan``).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from csql_sim.core.model.goal_spec import atom_text, state_atoms
from csql_sim.core.state.state_count import sample_state
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import write_atomic
from csql_sim.infra.provenance import provenance
from csql_sim.jobs.execute import execute_problem
from csql_sim.jobs.problems import DOMAIN_TEXT

REPORT_FORMAT, REPORT_VERSION = "csql-sim execute benchmark", 1
LIFTED = Path(__file__).resolve().parents[1] / "assets" / "rules" / "lifted.json"
NAMES = ("Ruby", "jade", "b2", "b10", "x-ray", "amber_1", "Slate", "ivory", "Q7", "crate-12", "box_3", "obsidian",
         "Zeta", "node-1-2", "b1", "C")


def named_task(k: int, rng: np.random.Generator) -> str:
    """The PDDL text of task k: n in 7..10 named objects, a hand-empty start, a partial goal."""
    n = int(rng.integers(7, 11))
    names = tuple(str(x) for x in rng.choice(NAMES, size=n, replace=False))
    start, end = sample_state(n, rng), sample_state(n, rng)
    while start.held is not None or end.held is not None:
        start, end = sample_state(n, rng), sample_state(n, rng)
    ons = sorted(a for a in state_atoms(end) if a[0] == "on")
    keep = [ons[i] for i in sorted(rng.choice(len(ons), size=int(rng.integers(2, n)), replace=False))]
    init = [atom_text(a, names) for a in sorted(state_atoms(start))]
    init += [f"(clear {names[i]})" for i in range(n) if start.is_clear(i)]
    goal = " ".join(atom_text(a, names) for a in keep)
    return (f"(define (problem named-{k:02d}) (:domain blocks) (:objects {' '.join(names)})\n"
            f" (:init {' '.join(init)})\n (:goal (and {goal})))\n")


def pyperplan_plan(problem: Path, domain: Path) -> Path:
    """pyperplan's plan for ``problem`` (gbf, hff), written beside it as ``<problem>.soln``."""
    from pyperplan import planner

    plan = planner.search_plan(str(domain), str(problem), planner.SEARCHES["gbf"], planner.HEURISTICS["hff"])
    if plan is None:
        raise CsqlError(f"pyperplan found no plan for {problem}")
    out = problem.with_name(problem.name + ".soln")
    planner.write_solution(plan, str(out))
    return out


def run_task(problem: Path, domain: Path, perception: str, seed: int) -> list[dict]:
    """The three runs of one task: its plan file, the lifted rules, GN1 (a refusal is a row that failed)."""
    plan = pyperplan_plan(problem, domain)
    rows = []
    for kind, source in (("plan", {"plan": plan}), ("lifted", {"rules": LIFTED}), ("gn1", {"planner": "gn1"})):
        began = time.monotonic()
        try:
            result = execute_problem(problem, domain, perception=perception, seed=seed, **source)
        except CsqlError as exc:  # a plan step that is not applicable, say: refused before any physics
            rows.append({"problem": problem.name, "source": kind, "reached": False, "reason": f"refused: {exc}"})
        else:
            rows.append({"problem": problem.name, "blocks": result.blocks, "partial": result.goal.partial,
                         "source": kind, "reached": result.reached, "actions": result.episode.length,
                         "wall_seconds": round(time.monotonic() - began, 1), "reason": result.reason})
        print(json.dumps(rows[-1]), flush=True)
    return rows


def summary(rows: list[dict]) -> dict:
    """Reached / runs per source and over all."""
    out = {kind: [sum(r["reached"] for r in rows if r["source"] == kind),
                  sum(r["source"] == kind for r in rows)] for kind in ("plan", "lifted", "gn1")}
    out["all"] = [sum(r["reached"] for r in rows), len(rows)]
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="output folder")
    parser.add_argument("--named", type=int, default=12, help="generated tasks (default 12)")
    parser.add_argument("--problems", type=Path, help="a folder of further PDDL problems")
    parser.add_argument("--domain", type=Path, help="their domain file (with --problems)")
    parser.add_argument("--seed", type=int, default=2026, help="seeds the generated tasks (default 2026)")
    parser.add_argument("--perception", choices=("pose", "camera"), default="camera")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing report.json")
    args = parser.parse_args(argv)
    try:
        report = args.out / "report.json"
        if report.exists() and not args.overwrite:
            raise CsqlError(f"{report} exists; give --overwrite to replace it")
        if (args.problems is None) != (args.domain is None):
            raise CsqlError("give --problems DIR and --domain FILE together")
        args.out.mkdir(parents=True, exist_ok=True)
        domain = write_atomic(args.out / "domain.pddl", DOMAIN_TEXT)
        rng = np.random.default_rng(args.seed)
        tasks = [(write_atomic(args.out / f"named-{k:02d}.pddl", named_task(k, rng)), domain)
                 for k in range(1, args.named + 1)]
        if args.problems is not None:
            tasks += [(p, args.domain) for p in sorted(args.problems.glob("*.pddl"))
                      if "(define (domain" not in p.read_text(errors="replace").lower()]
        rows = [row for problem, dom in tasks for row in run_task(problem, dom, args.perception, 0)]
    except CsqlError as exc:
        print(f"execute_benchmark: error: {exc}", file=sys.stderr)
        return 2
    record = provenance(command="benchmarks/execute_pddl.py", named=args.named, seed=args.seed,
                        perception=args.perception, problems=None if args.problems is None else str(args.problems))
    doc = {"format": REPORT_FORMAT, "version": REPORT_VERSION, "summary": summary(rows), "runs": rows,
           "provenance": record}
    write_atomic(report, json.dumps(doc, indent=1) + "\n")
    print(" ".join(f"{k} {v[0]}/{v[1]}" for k, v in doc["summary"].items()), f"(report in {report})")
    return 0 if doc["summary"]["all"][0] == doc["summary"]["all"][1] else 1


if __name__ == "__main__":
    sys.exit(main())
