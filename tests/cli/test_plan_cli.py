"""``plan`` past six blocks: relational states, the GN1 baseline, --pairs K by counting, refusals."""

import json
import re
from pathlib import Path

import numpy as np
import pytest

from csql_sim.cli import main
from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.policies.lifted_policy import LiftedPolicy
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.relational_message import format_large_message
from csql_sim.core.state.state_count import pair_count, sample_pairs
from csql_sim.core.state.world import LETTERS, action_at, successor

START_26 = ",".join(LETTERS)  # every block on the table
GOAL_26 = "ZYXWVUTSRQPONMLKJIHGFEDCBA"  # one tower, A on top


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def refused(capsys, tmp_path, *argv, names):
    """Exit status 2, one line on stderr naming ``names``, nothing on stdout, nothing written."""
    before = set(tmp_path.rglob("*"))
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == "", (code, out, err)
    assert err.count("\n") == 1 and re.match(r"csql-sim [a-z-]+: error: ", err) and "Traceback" not in err, err
    assert names in err, err
    assert set(tmp_path.rglob("*")) == before
    return err


def applied(start, steps):
    """The state reached by applying a plan's steps (their action codes) with the STRIPS successor."""
    state = start
    for step in steps:
        state = successor(state, action_at(step["code"] - 1, start.n))
    return state


@pytest.fixture(scope="module")
def ground_rules(tmp_path_factory):
    """A ground 3-block rule file from 'csql-sim train' (two trials: it only has to exist)."""
    path = tmp_path_factory.mktemp("ground") / "r3.yaml"
    assert main(["train", "--trials", "2", "--out", str(path), "--quiet"]) == 0
    return path


@pytest.fixture(scope="module")
def lifted_rules():
    """The shipped lifted Q-classifiers (``csql-sim train-lifted``, seed 0, learned on five blocks)."""
    path = Path(__file__).resolve().parents[2] / "assets" / "rules" / "lifted.json"
    assert isinstance(load_policy(path, 8), LiftedPolicy)
    return path


def test_lifted_rules_plan_26_blocks_and_a_sample_at_10(capsys, lifted_rules):
    code, out, _ = run(capsys, "plan", "--rules", lifted_rules, "--start", START_26, "--goal", GOAL_26, "--json")
    doc = json.loads(out)
    assert code == 0 and doc["planner"] == "rules" and doc["blocks"] == 26
    assert applied(parse_config(START_26), doc["plan"]) == parse_config(GOAL_26)
    assert doc["optimal_length"] == 50 <= doc["length"]
    code, out, _ = run(capsys, "plan", "--rules", lifted_rules, "--pairs", "10", "--blocks", "10", "--seed", "1",
                       "--json")
    doc = json.loads(out)
    drawn = sample_pairs(10, 10, np.random.default_rng(1))
    assert code == 0 and doc["pairs"] == doc["covered"] == 10
    for plan, (start, goal) in zip(doc["plans"], drawn, strict=True):
        assert applied(start, plan["plan"]) == goal and plan["optimal_length"] == optimal_length(start, goal)


def test_a_26_block_task_is_planned_and_its_steps_reach_the_goal(capsys):
    code, out, _ = run(capsys, "plan", "--planner", "gn1", "--start", START_26, "--goal", GOAL_26, "--json")
    doc = json.loads(out)
    start, goal = parse_config(START_26), parse_config(GOAL_26)
    assert code == 0 and doc["blocks"] == 26 and doc["planner"] == "gn1"
    assert applied(start, doc["plan"]) == goal
    assert doc["length"] == len(doc["plan"]) == doc["optimal_length"] == optimal_length(start, goal) == 50
    assert doc["optimal"] is True
    assert [s["name"] for s in doc["plan"][:2]] == ["pickup(Y)", "stack(Y,Z)"]
    code, out, _ = run(capsys, "plan", "--planner", "gn1", "--start", START_26, "--goal", GOAL_26)
    lines = out.splitlines()
    assert code == 0 and len(lines) == 51 and lines[0].split() == ["pickup(Y)", doc["plan"][0]["message"]]
    assert lines[-1].startswith("50 actions, optimal (exact optimum")


def test_a_large_state_message_carries_its_goal(capsys):
    start, goal = parse_config("ZA,YB,XC,DEFGHIJKLMNOPQRSTUVW"), parse_config(GOAL_26)
    message = format_large_message(start, goal)
    code, out, _ = run(capsys, "plan", "--planner", "gn1", "--start", message, "--json")
    doc = json.loads(out)
    assert code == 0 and doc["start"] == start.notation() and doc["goal"] == goal.notation()
    assert applied(start, doc["plan"]) == goal and doc["length"] >= doc["optimal_length"] == optimal_length(start, goal)
    assert run(capsys, "plan", "--planner", "gn1", "--start", message, "--goal", GOAL_26)[0] == 0
    code, _, err = run(capsys, "plan", "--planner", "gn1", "--start", message, "--goal", START_26)
    assert code == 2 and "contradicts the goal of the start message" in err


def test_plan_out_names_blocks_past_f(tmp_path, capsys):
    out = tmp_path / "p.plan"
    code, _, _ = run(capsys, "plan", "--planner", "gn1", "--start", "A,B,C,D,E,F,G,H", "--goal", "HGFEDCBA",
                     "--plan-out", out)
    lines = out.read_text().splitlines()
    assert code == 0 and lines[1:3] == ["(pick-up g)", "(stack g h)"] and lines[-1] == "; cost = 14 (unit cost)"


@pytest.mark.parametrize(("n", "k", "seed"), [(10, 40, 7), (26, 8, 3)])
def test_pairs_by_counting_are_seeded_and_every_goal_is_reached(capsys, n, k, seed):
    argv = ["plan", "--planner", "gn1", "--pairs", k, "--blocks", n, "--seed", seed, "--json"]
    code, out, _ = run(capsys, *argv)
    doc = json.loads(out)
    assert code == 0 and json.loads(run(capsys, *argv)[1])["plans"] == doc["plans"]  # the seed decides
    drawn = sample_pairs(n, k, np.random.default_rng(seed))
    assert [(p["start"], p["goal"]) for p in doc["plans"]] == [(s.notation(), g.notation()) for s, g in drawn]
    for plan, (start, goal) in zip(doc["plans"], drawn, strict=True):
        assert applied(start, plan["plan"]) == goal
        assert plan["optimal_length"] == optimal_length(start, goal) <= plan["length"] == len(plan["plan"])
        assert plan["optimal"] == (plan["length"] == plan["optimal_length"])
    optimal = sum(p["optimal"] for p in doc["plans"])
    ratio = np.mean([p["length"] / p["optimal_length"] for p in doc["plans"]])
    assert doc["pairs"] == doc["covered"] == k and doc["optimal"] == optimal and doc["blocks"] == n
    assert doc["mean_length_over_optimum"] == pytest.approx(ratio, abs=1e-6) and ratio >= 1
    other = json.loads(run(capsys, *argv[:-3], "--seed", seed + 1, "--json")[1])
    assert other["plans"] != doc["plans"]


def test_pairs_text_summary(capsys):
    code, out, _ = run(capsys, "plan", "--planner", "gn1", "--pairs", "20", "--blocks", "8")
    head = out.splitlines()[0]
    assert code == 0 and head.startswith("pairs: 20  solved: 20 (100.0%)  optimal: ")
    assert "mean length / optimum: 1.0" in head and "8 blocks, pairs drawn uniformly by counting (seed 0)" in out


def test_pairs_all_past_six_blocks_is_refused_naming_the_count(capsys, tmp_path):
    count = f"{pair_count(8):,}"
    assert count == "483,604,108,472"
    for argv in (["--pairs", "all"], ["--pairs", "all"], ["--pairs", "all", "--planner", "gn1"]):
        err = refused(capsys, tmp_path, "plan", "--blocks", "8", *argv, "--json", tmp_path / "r.json", names=count)
        assert "4.8 x 10^11" in err
    refused(capsys, tmp_path, "plan", "--planner", "gn1", "--blocks", "7", "--pairs", "4354614111",
            names="4,354,614,110")


def test_bfs_past_six_blocks_is_refused(capsys, tmp_path):
    for planner in ([], ["--planner", "bfs"]):
        refused(capsys, tmp_path, "plan", *planner, "--start", "A,B,C,D,E,F,G,H", "--goal", "HGFEDCBA",
                "--plan-out", tmp_path / "p.plan", names="BFS enumerates every state (695,417 at 8 blocks)")
        refused(capsys, tmp_path, "plan", *planner, "--blocks", "8", "--pairs", "5", "--json", tmp_path / "r.json",
                names="--planner gn1")


def test_a_ground_rule_file_past_six_blocks_is_refused(capsys, tmp_path, ground_rules):
    for argv in (["--start", "A,B,C,D,E,F,G,H", "--goal", "HGFEDCBA"], ["--blocks", "8", "--pairs", "5"]):
        err = refused(capsys, tmp_path, "plan", "--rules", ground_rules, *argv, "--json", tmp_path / "r.json",
                      names="is for 3 blocks, not 8")
        assert "lifted rules" in err
    refused(capsys, tmp_path, "plan", "--rules", ground_rules, "--planner", "gn1", "--blocks", "8", "--pairs", "5",
            names="--planner gn1 does not read --rules")


def test_27_blocks_is_refused_by_the_parser(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["plan", "--planner", "gn1", "--blocks", "27", "--pairs", "5"])
    _, err = capsys.readouterr()
    assert exit_.value.code == 2 and err.count("\n") == 1 and "must be an integer 2..26, got 27" in err


@pytest.mark.parametrize(("argv", "names"), [
    (["--start", "ABCDEFGG", "--goal", "ABCDEFGH"], "block G is used twice"),
    (["--start", "ABCDEFGH", "--goal", "ABC"], "block D is missing"),
    (["--start", "ABCDEFGH"], "--goal is missing"),
    (["--blocks", "9", "--start", "ABCDEFGH", "--goal", "HGFEDCBA"], "block I is missing"),
    (["--start", "S0011111111________0bcdefgh_0x"], "has 30 characters"),
    (["--start", "S0011111111________0bcdefgh_x"], "position 28"),
    (["--start", "ABCDEFGH", "--goal", "HGFEDCBA", "--pairs", "5"], "do not give --start"),
])
def test_malformed_large_tasks_are_one_line(capsys, tmp_path, argv, names):
    refused(capsys, tmp_path, "plan", "--planner", "gn1", *argv, names=names)


def test_gn1_and_the_enumerated_world_up_to_six_blocks(capsys):
    code, out, _ = run(capsys, "plan", "--planner", "gn1", "--start", "CBA", "--goal", "ABC", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["length"] == doc["optimal_length"] == 6 and "planner" not in doc
    code, out, _ = run(capsys, "plan", "--planner", "gn1", "--pairs", "all", "--blocks", "3")
    assert code == 0 and out.startswith("pairs: 462  covered: 462  optimal: 462")


def test_a_configuration_may_start_with_block_s(capsys):
    # 19 blocks, one tower with S at the bottom: a configuration, not a state message (it has no digit)
    assert main(["plan", "--start", "SRQPONMLKJIHGFEDCBA", "--goal", ",".join(LETTERS[:19]), "--planner", "gn1",
                 "--json", "-"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["blocks"] == 19 and doc["length"] == doc["optimal_length"] == 36


def test_plan_steps_carry_the_view_of_their_n():
    from csql_sim.cli.plan_view import plan_steps
    from csql_sim.core.state.world import Action, ActionKind

    stack = Action(ActionKind.STACK, 1, 0)
    assert plan_steps([stack], 3)[0] == {"code": "F", "name": "stack(B,A)", "message": "AF0000000100ba00"}
    assert plan_steps([stack], 7)[0] == {"code": 63, "name": "stack(B,A)", "message": "A1R0000000100ba00"}
    assert plan_steps([Action(ActionKind.PICKUP, 26)], 30)[0] == {"code": 30 * 29 + 27, "name": "pickup(AA)",
                                                                  "message": None}


@pytest.mark.parametrize("planner", ["gn1", "gn2"])
def test_the_named_baselines_plan_seeded_pairs_of_twelve_blocks_to_the_goal(capsys, planner):
    code, out, _ = run(capsys, "plan", "--planner", planner, "--pairs", 5, "--blocks", 12, "--seed", 3, "--json")
    doc = json.loads(out)
    drawn = sample_pairs(12, 5, np.random.default_rng(3))
    assert code == 0 and len(doc["plans"]) == 5
    for plan, (start, goal) in zip(doc["plans"], drawn, strict=True):
        assert applied(start, plan["plan"]) == goal and plan["length"] >= optimal_length(start, goal)
