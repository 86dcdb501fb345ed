"""Tall-tower blocks-world tasks of 25..1,000 blocks: the lifted rules, GN1 and Fast Downward side by side.

Regenerates docs/results/large_problems.md, the tall-tower benchmark's rows (the lifted rules, GN1, Fast Downward).

    python benchmarks/large_problems.py --out DIR [--sizes 25,50,100,200,500] [--tasks 30] [--seed 0]
        [--time-sizes 1000] [--time-tasks 5] [--runs 3] [--fd-tasks 30|K,K,...] [--fd-timeout 60]
        [--optimum-budget 60] [--retry-bounded] [--stage all|plan|optimum|report] [--rules assets/rules/lifted.json]

Tasks: ``csql-sim problems --distribution tall-towers`` (seeded, byte-identical per seed),
written to DIR/problems. Stages (each resumes: finished rows in its JSON-lines file are kept):

* ``plan`` (DIR/plans.jsonl): every task planned by the lifted rules and by GN1 from its
  PDDL file (parsing with the ``pddl`` library included), after one warm-up run that
  compiles the numba code; time per task is the median of ``--runs`` runs, in process CPU
  seconds (one core) and wall seconds. Fast Downward (``unified-planning`` +
  ``up-fast-downward``, the ``fast-downward`` engine, ``--fd-timeout`` s, a timeout counted
  unsolved) runs once on the first ``--fd-tasks`` tasks of each size; its time is wall
  seconds including unified-planning's parsing. The ``--time-sizes`` tasks are timed only.
* ``optimum`` (DIR/optimum.jsonl): per task the lower bound 2 x misplaced and the optimum
  by the deadlock characterization (implicit hitting sets with CP-SAT when OR-Tools is
  installed, :func:`~csql_sim.core.measure.bounds.hitting_set_optimum`, else the branch and
  bound), within ``--optimum-budget`` s, proven or bounded; the shortest plan found
  narrows a bounded optimum from above.
* ``report`` (DIR/table.md, DIR/time_per_task.png): the table and the plot of time per
  task against n with the fitted log-log slope.

Cost / optimum is the total cost over the tasks a planner solved divided by the total of
their optima, where a task's optimum is only bounded its lower bound (so the ratio is
then an upper bound on the true one).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from pddl import parse_problem

from csql_sim.core.measure.bounds import bounded_optimum, cpsat_available, hitting_set_optimum, lower_bound
from csql_sim.core.policies.lifted_policy import load_lifted_policy
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.state import State
from csql_sim.core.state.world import TABLE
from csql_sim.jobs.baselines import NAMED_POLICIES
from csql_sim.jobs.problems import drawn_problems

DISTRIBUTION = "tall-towers"


def read_task(path: Path) -> tuple[State, State]:
    """Start and goal of a drawn problem (objects b1..bN) read with the ``pddl`` library."""
    problem = parse_problem(path)
    index = {f"b{i + 1}": i for i in range(len(problem.objects))}

    def state(atoms: object) -> State:
        support = [TABLE] * len(index)
        for atom in atoms:
            if atom.name == "on":
                top, below = (t.name for t in atom.terms)
                support[index[top]] = index[below]
        return State(tuple(support))

    return state(problem.init), state(problem.goal.operands)


def plan_ours(name: str, path: Path, rules: str) -> tuple[bool, int | None]:
    """Parse and plan one task with the lifted rules or a named baseline (GN1, GN2); (solved, cost)."""
    policy = load_lifted_policy(rules) if name == "rules" else NAMED_POLICIES[name]()
    start, goal = read_task(path)
    run = rollout_relational(policy, start, goal)
    return run.reached, run.length


def _cpu() -> float:
    """CPU seconds of this process and of its finished children (Fast Downward runs in one)."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def timed(fn: object, *args: object) -> tuple[object, float, float]:
    """fn's result, its CPU seconds (with its child processes') and its wall seconds."""
    c0, w0 = _cpu(), time.perf_counter()
    out = fn(*args)
    return out, _cpu() - c0, time.perf_counter() - w0


def plan_fd(domain: Path, path: Path, timeout: float) -> tuple[bool, int | None]:
    """Fast Downward through unified-planning; (solved, cost). A timeout is unsolved."""
    from unified_planning.io import PDDLReader
    from unified_planning.shortcuts import OneshotPlanner, get_environment

    get_environment().credits_stream = None
    problem = PDDLReader().parse_problem(str(domain), str(path))
    here = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="fd-") as scratch:  # its translator writes output.sas here
        os.chdir(scratch)
        try:
            with OneshotPlanner(name="fast-downward") as planner:
                result = planner.solve(problem, timeout=timeout)
        finally:
            os.chdir(here)
    if result.plan is None or "SOLVED" not in result.status.name:
        return False, None
    return True, len(result.plan.actions)


def _done(path: Path, key: tuple[str, ...]) -> set[tuple]:
    if not path.exists():
        return set()
    return {tuple(json.loads(line)[k] for k in key) for line in path.read_text().splitlines() if line.strip()}


def _append(path: Path, row: dict) -> None:
    with path.open("a") as f:
        f.write(json.dumps(row) + "\n")
        f.flush()
        os.fsync(f.fileno())
    print(json.dumps(row), file=sys.stderr, flush=True)


def write_tasks(folder: Path, sizes: list[int], tasks: int, seed: int) -> dict[int, list[Path]]:
    """The problem files (written once; the same bytes for the same seed)."""
    folder.mkdir(parents=True, exist_ok=True)
    out: dict[int, list[Path]] = {}
    for name, text in drawn_problems(DISTRIBUTION, sizes, tasks, seed):
        path = folder / name
        if path.exists() and path.read_text() != text:
            raise SystemExit(f"{path} differs from the seeded task; give another --out")
        if not path.exists():
            path.write_text(text)
        if name != "domain.pddl":
            out.setdefault(int(name.split("-")[-2]), []).append(path)
    return out


def fd_tasks(args: argparse.Namespace, n: int) -> int:
    """How many of the tasks of size n Fast Downward gets (``--fd-tasks``: one count, or one per size)."""
    counts = [int(c) for c in args.fd_tasks.split(",")]
    sizes = [int(s) for s in args.sizes.split(",")]
    return counts[0] if len(counts) == 1 else dict(zip(sizes, counts, strict=True)).get(n, 0)


def stage_plan(args: argparse.Namespace, tasks: dict[int, list[Path]], timing_only: set[int]) -> None:
    """Plan every task (module docstring), appending to plans.jsonl."""
    log = Path(args.out) / "plans.jsonl"
    done = _done(log, ("planner", "task"))
    first = tasks[min(tasks)][0]
    for name in ("rules", *NAMED_POLICIES):
        plan_ours(name, first, args.rules)  # warm-up: numba compiles (or loads its cache) here
    domain = Path(args.out) / "problems" / "domain.pddl"
    for n in sorted(tasks):
        for name in ("rules", *NAMED_POLICIES, "fd"):
            chosen = tasks[n][:fd_tasks(args, n)] if name == "fd" else tasks[n]
            if name == "fd" and n in timing_only:
                continue
            for path in chosen:
                if (name, path.name) in done:
                    continue
                if name == "fd":
                    (solved, cost), cpu, wall = timed(plan_fd, domain, path, args.fd_timeout)
                    cpus, walls = [cpu], [wall]
                else:
                    runs = [timed(plan_ours, name, path, args.rules) for _ in range(args.runs)]
                    (solved, cost), cpus, walls = runs[0][0], [r[1] for r in runs], [r[2] for r in runs]
                _append(log, {"planner": name, "n": n, "task": path.name, "solved": solved, "cost": cost,
                              "cpu_s": statistics.median(cpus), "wall_s": statistics.median(walls),
                              "runs": len(cpus)})


def stage_optimum(args: argparse.Namespace, tasks: dict[int, list[Path]], timing_only: set[int]) -> None:
    """Lower bound and optimum of every task, appending to optimum.jsonl."""
    log = Path(args.out) / "optimum.jsonl"
    done = _done(log, ("task",))
    if args.retry_bounded:  # measure the bounded ones again (the report keeps each task's tightest bounds)
        done -= {(r["task"],) for r in map(json.loads, log.read_text().splitlines()) if not r["proven"]}
    best: dict[str, int] = {}
    plans = Path(args.out) / "plans.jsonl"
    if plans.exists():
        for line in plans.read_text().splitlines():
            row = json.loads(line)
            if row["solved"]:
                best[row["task"]] = min(best.get(row["task"], row["cost"]), row["cost"])
    solver = hitting_set_optimum if cpsat_available() else bounded_optimum
    for n in sorted(tasks):
        if n in timing_only:
            continue
        for path in tasks[n]:
            if (path.name,) in done:
                continue
            start, goal = read_task(path)
            t0 = time.perf_counter()
            bound = solver(start, goal, args.optimum_budget, best.get(path.name))
            _append(log, {"n": n, "task": path.name, "lower_bound": lower_bound(start, goal), "lower": bound.lower,
                          "upper": bound.upper, "proven": bound.proven, "method": bound.method,
                          "seconds": round(time.perf_counter() - t0, 2)})


def main(argv: list[str] | None = None) -> int:
    """Parse the options and run the stages asked for."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="folder for the problems, the JSON lines and the report")
    parser.add_argument("--sizes", default="25,50,100,200,500", help="sizes measured in full")
    parser.add_argument("--tasks", type=int, default=30, help="tasks per size (default 30)")
    parser.add_argument("--time-sizes", default="1000", help="sizes only timed, for the plot (default 1000)")
    parser.add_argument("--time-tasks", type=int, default=5, help="tasks per timed-only size (default 5)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the tasks (default 0)")
    parser.add_argument("--runs", type=int, default=3, help="timed runs per task, median (default 3)")
    parser.add_argument("--fd-tasks", default="30", help="tasks per size given to Fast Downward: K, or one K "
                        "per size in --sizes (default 30)")
    parser.add_argument("--fd-timeout", type=float, default=60.0, help="Fast Downward's seconds per task")
    parser.add_argument("--optimum-budget", type=float, default=60.0, help="seconds per task for the optimum")
    parser.add_argument("--retry-bounded", action="store_true", help="optimum stage: measure the tasks whose "
                        "optimum is only bounded again (with this --optimum-budget)")
    parser.add_argument("--stage", choices=("all", "plan", "optimum", "report"), default="all")
    parser.add_argument("--rules", default="assets/rules/lifted.json", help="lifted Q-classifier file")
    args = parser.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",") if s]
    timing_only = {int(s) for s in args.time_sizes.split(",") if s} - set(sizes)
    folder = Path(args.out) / "problems"
    tasks = write_tasks(folder, sizes, args.tasks, args.seed)
    for n, paths in write_tasks(folder, sorted(timing_only), args.time_tasks, args.seed).items():
        tasks[n] = paths
    if args.stage in ("all", "plan"):
        stage_plan(args, tasks, timing_only)
    if args.stage in ("all", "optimum"):
        stage_optimum(args, tasks, timing_only)
    if args.stage in ("all", "report"):
        from blocks_benchmark_report import report  # the report's half of this script, beside it

        print(report(Path(args.out)))
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    np.seterr(all="ignore")
    sys.exit(main())
