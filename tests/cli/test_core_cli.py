import json
import subprocess
import sys

import pytest

from csql_sim.cli import main
from csql_sim.notation import parse_config
from csql_sim.planner import distance


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
    rules = json.loads(out)
    assert len(rules) == 64 and set(rules[0]) == {"kind", "condition", "action"}


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
    code, out, _ = run(capsys, "plan", "--all", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["pairs"] == doc["covered"] == doc["optimal"] == 462


@pytest.mark.parametrize(
    "argv",
    [
        ["plan", "--start", "CBD", "--goal", "BAC"],
        ["plan", "--start", "CBA", "--goal", "BA"],
        ["plan", "--start", "CBA", "--goal", "BAA"],
        ["plan", "--start", "CBA", "--goal", "DCBA"],
        ["plan", "--start", "S0111000txt0000C", "--goal", "BAC"],
        ["plan", "--start", "CBA"],
        ["plan", "--rules", "/nonexistent/rules.yaml", "--all"],
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
    assert proc.stderr.strip() == "csql-sim: error: unknown block D for a 3-block world in 'CBD'"
