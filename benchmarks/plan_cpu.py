"""CPU seconds of ``csql-sim plan --problem`` on a large task: the whole command, and its phases in one run.

Regenerates docs/results/large_problems.md, its table of CPU seconds of one 500-block plan command.

    python benchmarks/plan_cpu.py [--blocks 500] [--seed 0] [--rules builtin|FILE] [--repeat 3]
                                  [--optimum-budget 1] [--problem FILE]

The task is the first tall tower of ``csql-sim problems --blocks N --seed S`` (a tuning task),
unless ``--problem`` names one. Two measurements, each in fresh processes (nothing warm):

* **whole command**: ``csql-sim plan --problem P --plan-out FILE --overwrite`` run ``--repeat``
  times, user + system CPU seconds of the child (``resource.getrusage(RUSAGE_CHILDREN)``); min,
  median and max are printed;
* **phases**: ``--repeat`` child processes that do what the command does, step by step, each
  printing the CPU seconds (``time.process_time``) of each: interpreter start-up, imports (the CLI's),
  reading the PDDL problem, loading the rules, (the given atoms) importing numba and loading the
  deadlock kernels from its cache (the planner's first decision does it in the command),
  planning, checking the plan against the goal and spelling it, measuring the optimum
  (``--optimum-budget``, as the command's default of 1 s) and writing the plan file; the
  median of each phase is printed (so the phases need not add up to the whole command's median).

``--rules FILE`` measures another planner the same way: a lifted rule file, or a file of
classifiers over generated features (its formulation's hand decides the rollout), e.g. the
generated-feature path. The whole command includes building the parser and printing the
report, which the phases leave out. Python's bytecode should be compiled beforehand
(``python -m compileall csql_sim``): where ``PYTHONDONTWRITEBYTECODE`` is set, every fresh
process otherwise compiles the package's modules again (about 0.3 s).

Every figure is measured in one run of this script, on this machine; none is remembered.
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PHASES = r'''
import json, sys, time
t = {"start-up": time.process_time()}
mark = time.process_time()
def lap(name):
    global mark
    now = time.process_time(); t[name] = now - mark; mark = now
import csql_sim.cli.plan  # noqa: F401 - the command's own imports
from csql_sim.api.planning import policy_maker
from csql_sim.core.files.ipc_plan import write_ipc_plan_lines
from csql_sim.core.model.goal_spec import goal_target
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.files.plan_spelling import spelled_plan_lines, spelling_of
from csql_sim.jobs.plan_problems import _end, measure, read_blocks_problem
lap("imports")
problem, rules, budget, out = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
blocks = read_blocks_problem(problem)
start, target = blocks.start, goal_target(blocks.goal, blocks.start)
lap("read problem")
policy = policy_maker(None if rules == "builtin" else rules, "builtin" if rules == "builtin" else "rules")(blocks.n)
lap("load rules")
if rules == "builtin":  # the given atoms' planner loads these at its first decision
    import numpy as np
    from csql_sim.core.state import deadlock_kernel as k
    i, b = np.full(2, -1, np.int64), np.zeros(2, np.bool_)
    k.deadlocked(i, i, b, b.copy()); k.deadlock_cover(i, i, i, b, b, b.copy())
    k.deadlock_counts(i, i, i, b, np.zeros(0, np.int64), b.copy())
    lap("numba: import, kernels from its cache")
run = rollout_relational(policy, start, target, hand=getattr(getattr(policy, "form", None), "hand", True))
lap("plan")
assert run.reached and blocks.goal.satisfied(_end(start, run.actions))
lines = spelled_plan_lines(run.actions, spelling_of(blocks))
lap("check and spell")
measure(start, target, len(run.actions), budget)
lap("measure optimum")
write_ipc_plan_lines(lines, out, header="; plan")
lap("write plan")
t["actions"] = len(run.actions)
t["linalg"] = "scipy.linalg" in sys.modules
print(json.dumps(t))
'''


def child_cpu(command: list[str]) -> float:
    """User + system CPU seconds of one child process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(command, check=True, capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def phase_run(problem: Path, args: argparse.Namespace, folder: Path) -> dict:
    """The CPU seconds of each phase in one fresh process (:data:`PHASES`), with the plan's length."""
    done = subprocess.run([sys.executable, "-c", PHASES, str(problem), args.rules, str(args.optimum_budget),
                           str(folder / "phases.txt")], check=True, capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def task(args: argparse.Namespace, folder: Path) -> Path:
    """The problem file: ``--problem``, or the first tall tower of ``csql-sim problems``."""
    if args.problem:
        return Path(args.problem)
    cli = [sys.executable, "-c", "from csql_sim.cli import console; console()"]
    subprocess.run([*cli, "problems", "--blocks", str(args.blocks), "--seed", str(args.seed), "--out",
                    str(folder / "p"), "--quiet"], check=True, capture_output=True)
    return next(p for p in sorted((folder / "p").glob("*.pddl")) if p.name != "domain.pddl")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--blocks", type=int, default=500)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--problem", help="a PDDL problem instead of the generated tall tower")
    parser.add_argument("--rules", default="builtin", help="builtin (the given atoms) or a lifted rule file")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--optimum-budget", type=float, default=1.0)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        problem = task(args, folder)
        cli = [sys.executable, "-c", "from csql_sim.cli import console; console()", "plan", "--problem", str(problem),
               "--plan-out", str(folder / "plan.txt"), "--overwrite", "--optimum-budget", str(args.optimum_budget)]
        if args.rules != "builtin":
            cli += ["--rules", args.rules]
        began = time.strftime("%Y-%m-%d")
        whole = [child_cpu(cli) for _ in range(args.repeat)]
        runs = [phase_run(problem, args, folder) for _ in range(args.repeat)]
    actions, linalg = runs[0].pop("actions"), runs[0].pop("linalg")
    phases = {name: statistics.median(run[name] for run in runs) for name in runs[0]}
    print(f"{began}: {problem.name}, rules {args.rules}, {actions} actions, optimum budget {args.optimum_budget} s, "
          f"scipy.linalg imported: {'yes' if linalg else 'no'}")
    print(f"whole command, CPU s over {args.repeat} fresh runs: min {min(whole):.2f} / median "
          f"{statistics.median(whole):.2f} / max {max(whole):.2f}")
    print(f"| phase (median of {args.repeat} fresh runs) | CPU s |\n|---|---:|")
    for name, seconds in phases.items():
        print(f"| {name} | {seconds:.2f} |")
    print(f"| total | {sum(phases.values()):.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
