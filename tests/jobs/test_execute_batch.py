"""evaluate --problems: every PDDL problem of a folder on the arm, reported like evaluate."""

import json
import shutil
from pathlib import Path

from csql_sim.cli import main

PROBLEMS = Path(__file__).resolve().parents[1] / "data" / "problems"


def test_every_problem_with_its_plan_reaches_the_goal(capsys):
    assert main(["evaluate", "--problems", str(PROBLEMS), "--plans", str(PROBLEMS), "--json", "--quiet"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["format"] == "csql-sim problems report" and report["version"] == 1
    assert report["problems"] == report["reached"] == len(list(PROBLEMS.glob("blocks*.pddl"))) == 6
    assert all(r["plan"] == r["problem"].replace(".pddl", ".plan") for r in report["runs"])
    sizes = {r["problem"]: int(r["problem"][6]) for r in report["runs"]}  # blocks<N>-<k>.pddl
    assert all(r["legend"] == dict(zip("abcde", ["red", "green", "blue", "yellow", "purple"][:sizes[r["problem"]]],
                                       strict=False)) for r in report["runs"])


def test_without_plans_the_bfs_planner_runs_each_problem(capsys):
    assert main(["evaluate", "--problems", str(PROBLEMS), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert printed.startswith("6/6 problems reached on the arm")
    assert "    legend: a = red, b = green, c = blue\n" in printed


def test_a_wrong_plan_is_a_refused_row_and_exit_1(tmp_path, capsys):
    plans = tmp_path / "plans"
    shutil.copytree(PROBLEMS, plans)
    (plans / "blocks3-01.plan").write_text("(pick-up a)\n")  # a is under b: not applicable
    assert main(["evaluate", "--problems", str(PROBLEMS), "--plans", str(plans), "--json", "--quiet"]) == 1
    rows = {r["problem"]: r for r in json.loads(capsys.readouterr().out)["runs"]}
    assert not rows["blocks3-01.pddl"]["reached"] and rows["blocks3-01.pddl"]["reason"].startswith("refused:")
    assert "line 1" in rows["blocks3-01.pddl"]["reason"] and rows["blocks3-01.pddl"]["legend"] is None
    assert sum(r["reached"] for r in rows.values()) == 5


def test_a_missing_plan_or_an_empty_folder_is_refused_before_any_episode(tmp_path, capsys):
    assert main(["evaluate", "--problems", str(PROBLEMS), "--plans", str(tmp_path), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no plan for blocks3-01.pddl" in err
    assert main(["evaluate", "--problems", str(tmp_path), "--quiet"]) == 2
    assert "holds no PDDL problem" in capsys.readouterr().err
