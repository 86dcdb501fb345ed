import json
import subprocess
import sys

import pytest

from csql_sim.cli import main
from csql_sim.core.model.search import distance
from csql_sim.core.state.notation import parse_config


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_states(capsys):
    code, out, _ = run(capsys, "states", "--blocks", "3")
    lines = out.splitlines()
    assert code == 0 and lines[0].startswith("22 states") and len(lines) == 23
    code, out, _ = run(capsys, "states", "--blocks", "4", "--json")
    doc = json.loads(out)
    assert doc["count"] == 125 == len(doc["states"])
    assert parse_config(doc["states"][7]["notation"]).n == 4


def test_rules(capsys):
    code, out, _ = run(capsys, "rules")
    lines = out.splitlines()
    assert code == 0 and len(lines) == 36
    assert lines[0] == "R S#1#####b#####0# A10000001000ab00"
    assert lines[-1] == "R SI############## S0#01#####b###0#"
    code, out, _ = run(capsys, "rules", "--blocks", "4", "--json")
    doc = json.loads(out)
    assert doc["blocks"] == 4 and doc["count"] == 64 == len(doc["rules"])
    assert set(doc["rules"][0]) == {"kind", "condition", "action"}


def test_plan_test_task(capsys):
    code, out, _ = run(capsys, "plan", "--start", "CBA", "--goal", "BAC")
    assert code == 0 and len(out.splitlines()) == 8
    code, out, _ = run(capsys, "plan", "--start", "S0100000bct0000C", "--goal", "bac", "--json")
    doc = json.loads(out)
    assert doc["start"] == "CBA" and doc["goal"] == "BAC" and doc["length"] == 8
    assert doc["plan"][0] == {"code": "1", "name": "unstack(A,B)", "message": "A10000001000ab00"}


def test_plan_four_blocks(capsys):
    code, out, _ = run(capsys, "plan", "--start", "DCBA", "--goal", "ABCD", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["length"] == distance(parse_config("DCBA"), parse_config("ABCD"))


def test_plan_all_bfs(capsys):
    code, out, _ = run(capsys, "plan", "--pairs", "all", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["pairs"] == doc["covered"] == doc["optimal"] == 462
    # a plan step is the same object in plan --all as in a single plan
    pair = next(p for p in doc["plans"] if p["start"] == "CBA" and p["goal"] == "BAC")
    code, out, _ = run(capsys, "plan", "--start", "CBA", "--goal", "BAC", "--json")
    assert pair["plan"] == json.loads(out)["plan"] and pair["length"] == pair["optimal_length"] == 8


def test_plan_start_is_goal_says_so(capsys):
    code, out, _ = run(capsys, "plan", "--start", "CBA", "--goal", "CBA")
    assert code == 0 and out.strip() == "the start CBA is the goal: 0 actions"
    code, out, _ = run(capsys, "plan", "--start", "CBA", "--goal", "cba", "--json")
    assert code == 0 and json.loads(out)["length"] == 0 and json.loads(out)["plan"] == []


def test_state_message_start_keeps_its_goal(capsys):
    # goal code C of the message is BAC: no --goal needed, and a contradicting --goal is an error
    code, out, _ = run(capsys, "plan", "--start", "S0100000bct0000C", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["goal"] == "BAC" and doc["length"] == 8
    code, out, err = run(capsys, "plan", "--start", "S0100000bct0000C", "--goal", "A,B,C")
    assert code == 2 and out == "" and "contradicts" in err and "BAC" in err


def test_plan_without_a_plan_exits_1(tmp_path, capsys):
    from csql_sim.core.classifiers.r_classifier import r_classifiers
    from csql_sim.core.files.rulebase import RuleBase, save

    empty = save(tmp_path / "empty.yaml", RuleBase(3, list(r_classifiers(3))))
    code, out, err = run(capsys, "plan", "--rules", str(empty), "--start", "CBA", "--goal", "BAC")
    assert code == 1 and out == "" and "no plan from CBA to BAC" in err
    code, out, err = run(capsys, "plan", "--rules", str(empty), "--start", "CBA", "--goal", "BAC", "--json")
    assert code == 1 and json.loads(out)["plan"] is None and "no Q-classifier" in json.loads(out)["reason"]
    code, out, _ = run(capsys, "plan", "--rules", str(empty), "--pairs", "all", "--json")
    assert code == 1 and json.loads(out)["covered"] == 0 and json.loads(out)["plans"][0]["plan"] is None


def test_json_to_a_file_replaces_the_text(tmp_path, capsys):
    target = tmp_path / "states.json"
    code, out, err = run(capsys, "states", "--json", str(target))
    assert code == 0 and out == "" and str(target) in err
    assert json.loads(target.read_text())["count"] == 22


@pytest.mark.parametrize(
    "argv",
    [
        ["plan", "--start", "CBD", "--goal", "BAC"],
        ["plan", "--start", "CBA", "--goal", "BA"],
        ["plan", "--start", "CBA", "--goal", "BAA"],
        ["plan", "--start", "CBA", "--goal", "DCBA"],
        ["plan", "--start", "S0111000txt0000C", "--goal", "BAC"],
        ["plan", "--start", "CBA"],
        ["plan", "--start", "S0100000bct0000C", "--goal", "CBA"],
        ["plan", "--rules", "/nonexistent/rules.yaml", "--pairs", "all"],
        ["states", "--blocks", "9"],
        ["states", "--blocks", "x"],
        ["frobnicate"],
        ["plan", "--start", "CBA", "--goal", "BAC", "--bogus"],
    ],
)
def test_error_paths_exit_2_with_one_line(capsys, argv):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse usage errors
        code = exc.code
    out, err = capsys.readouterr()
    assert code == 2
    assert out == ""
    assert len(err.strip().splitlines()) == 1 and "error" in err


def test_console_entry_point_no_traceback():
    proc = subprocess.run(
        [sys.executable, "-m", "csql_sim", "plan", "--start", "CBD", "--goal", "BAC"],
        capture_output=True, text=True, check=False,
    )
    assert proc.returncode == 2
    assert proc.stderr.strip() == "csql-sim plan: error: unknown block D for a 3-block world in 'CBD'"


def test_the_console_freezes_what_is_left_before_it_exits(monkeypatch, capsys):
    import gc

    from csql_sim.cli import console

    monkeypatch.setattr(sys, "argv", ["csql-sim", "plan", "--start", "CBA", "--goal", "ABC"])
    before = gc.get_freeze_count()
    try:
        with pytest.raises(SystemExit) as done:
            console()
        assert done.value.code == 0 and gc.get_freeze_count() > before  # the exit's collection skips them
    finally:
        gc.unfreeze()
    assert capsys.readouterr().out.strip()


def test_plan_pairs_sample_is_seeded_and_bounded(capsys):
    code, out, _ = run(capsys, "plan", "--pairs", "5", "--seed", "3", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["pairs"] == 5 and doc["provenance"]["parameters"]["seed"] == 3
    again = json.loads(run(capsys, "plan", "--pairs", "5", "--seed", "3", "--json")[1])
    assert [(p["start"], p["goal"]) for p in again["plans"]] == [(p["start"], p["goal"]) for p in doc["plans"]]
    code, out, err = run(capsys, "plan", "--pairs", "463")
    assert code == 2 and out == "" and "more than the 462 start/goal pairs" in err


def test_plan_pairs_without_rules_says_it_checks_bfs_against_itself(capsys):
    assert main(["plan", "--pairs", "5", "--blocks", "3"]) == 0
    out = capsys.readouterr().out
    assert "pairs: 5" in out and "BFS planner checked against BFS" in out and "--rules" in out


def test_plan_out_writes_an_ipc_plan_that_execute_reads(tmp_path, capsys):
    """plan --plan-out round-trips: the IPC file passes execute's symbolic check and reaches the goal on the arm."""
    from pathlib import Path


    problem = Path(__file__).resolve().parents[1] / "data" / "problems" / "blocks3-01.pddl"
    plan = tmp_path / "p.plan"
    assert main(["plan", "--start", "CAB", "--goal", "CA,B", "--plan-out", str(plan)]) == 0
    assert plan.read_text().startswith("; csql-sim plan CAB -> B,CA")
    capsys.readouterr()
    assert main(["execute", "--problem", str(problem), "--plan", str(plan), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["reached"] is True and len(report["steps"]) == 2
