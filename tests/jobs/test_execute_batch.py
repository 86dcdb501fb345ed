"""evaluate --problems: every PDDL problem of a folder on the arm, reported like evaluate."""

import json
import shutil
from pathlib import Path

import pytest

from csql_sim.cli import main
from csql_sim.core.files.pddl_import import name_key

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


LARGE = PROBLEMS.parent / "large"


@pytest.mark.parametrize("source", [["--plans", "plans"], ["--planner", "gn1"], ["--rules", "builtin"]])
def test_twelve_named_cubes_reach_their_partial_goal_with_a_plan_gn1_or_the_lifted_rules(tmp_path, capsys, source):
    """Past ten cubes; ``--planner gn1`` with ``--problems`` was refused (issue 54)."""
    for folder in ("probs", "plans"):
        (tmp_path / folder).mkdir()
    shutil.copy(LARGE / "blocks12-names.pddl", tmp_path / "probs")
    shutil.copy(LARGE / "blocks12-names.plan", tmp_path / "plans")
    source = [str(tmp_path / a) if a == "plans" else a for a in source]
    assert main(["evaluate", "--problems", str(tmp_path / "probs"), *source, "--json", "--quiet"]) == 0
    report = json.loads(capsys.readouterr().out)
    (run,) = report["runs"]
    assert report["reached"] == 1 and run["reached"] and run["reason"] == "" and 6 <= run["actions"] <= 8
    assert run["plan"] == ("blocks12-names.plan" if "--plans" in source else None)
    assert list(run["legend"]) == sorted(run["legend"], key=name_key) and "x-ray" in run["legend"]
    planner = {"--planner": "gn1", "--plans": None, "--rules": None}[source[0]]
    assert report["provenance"]["parameters"]["planner"] == planner
