"""Class 1 of issue 49: a tower of about a thousand blocks or more plans, within the 2,000-object limit.

Before the fix GN1's well-placed test walked each tower recursively
(``goal_relations.well_placed``), so ``plan --problem`` on one tower of 1,200 blocks died with
RecursionError, and with ``--problems`` the whole batch died instead of one row. Every walk
over a tower is iterative now (well placed, the goal detectors, ranking a state, the target of
a partial goal). The plans are replayed here by the test's own 4-operator simulator.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hostile_cli import csql
from sweep4 import judged, replay_4op, tower_problem

LIFTED = Path(__file__).resolve().parents[2] / "assets" / "rules" / "lifted.json"
N = 1100
"""Taller than Python's recursion limit (1,000): the recursive walk failed here."""


def upside_down(n: int) -> dict[str, str]:
    names = [f"b{i}" for i in range(1, n + 1)]
    return {names[-1]: "table", **{a: b for a, b in zip(names, names[1:], strict=False)}}


@pytest.mark.parametrize("budget", [0, 5])
def test_pp_tower_gn1_plans(work: Path, budget: int) -> None:
    """pp-tower1200-gn1, pp-tower1200-budget: the plan, every action applicable, reaching the goal, 2n actions."""
    tower_problem(work, "p.pddl", N)
    run = judged(work, lambda: csql(work, "plan", "--problem", "p.pddl", "--planner", "gn1", "--optimum-budget",
                                    budget, "--plan-out", "out.plan", "--quiet"), outputs=("out.plan",))
    assert run.returncode == 0 and run.stderr == "", run.stderr
    plan = (work / "out.plan").read_text()
    assert replay_4op(plan, [f"b{i}" for i in range(1, N + 1)]) == upside_down(N)
    assert sum(1 for line in plan.splitlines() if line.startswith("(")) == 2 * N  # each block moves once: optimal


def test_pp_tower_problems_gives_its_row(work: Path) -> None:
    """pp-tower1200-problems: the tall tower is a row of the batch, reached, beside a small problem."""
    (work / "pr").mkdir()
    tower_problem(work / "pr", "tall.pddl", N)
    tower_problem(work / "pr", "small.pddl", 4)
    run = csql(work, "plan", "--problems", "pr", "--planner", "gn1", "--optimum-budget", 0, "--json")
    assert run.returncode == 0 and run.stderr == "", run.stderr
    rows = {Path(row["problem"]).name: row for row in json.loads(run.stdout)["rows"]}
    assert rows["tall.pddl"]["cost"] == 2 * N and rows["small.pddl"]["cost"] == 8
    assert all(row["solved"] for row in rows.values())


@pytest.mark.slow
def test_a_tower_of_2000_blocks_upside_down_plans_with_gn1_and_lifted_rules_bfs_refuses(work: Path) -> None:
    n = 2000
    tower_problem(work, "p.pddl", n)
    names = [f"b{i}" for i in range(1, n + 1)]
    for planner in (("--planner", "gn1"), ("--rules", LIFTED)):
        run = csql(work, "plan", "--problem", "p.pddl", *planner, "--optimum-budget", 0, "--plan-out", "out.plan",
                   "--overwrite", "--quiet", timeout=600)
        assert run.returncode == 0 and run.stderr == "", run.stderr
        plan = (work / "out.plan").read_text()
        assert replay_4op(plan, names) == upside_down(n)
        assert sum(1 for line in plan.splitlines() if line.startswith("(")) == 2 * n
    (work / "out.plan").unlink()
    refused = judged(work, lambda: csql(work, "plan", "--problem", "p.pddl", "--planner", "bfs", "--plan-out",
                                        "out.plan"))
    refused.refused("BFS", "2000 blocks")
