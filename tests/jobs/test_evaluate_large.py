"""``evaluate`` with 7..10 cubes: pairs sampled by counting, lifted policies only, the exact optimum."""

import json

import numpy as np
import pytest

from csql_sim.cli import main
from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.files.rulebase import RuleBase, save
from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state import default_names
from csql_sim.core.state.state_count import pair_count, sample_pairs
from csql_sim.core.state.world import State, action_name, legal_actions, successor
from csql_sim.infra.errors import CsqlError
from csql_sim.jobs.evaluate import PolicyData, evaluate, make_specs
from csql_sim.jobs.execute import execute_task
from csql_sim.jobs.render import render_episode


def test_pairs_past_six_blocks_are_sampled_by_counting_from_the_seed():
    specs = make_specs(8, 5, seeds=2, sample_seed=11)
    drawn = sample_pairs(8, 5, np.random.default_rng(11))
    assert [(s.start, s.goal) for s in specs[::2]] == [(a.notation(), b.notation()) for a, b in drawn]
    assert [s.seed for s in specs] == list(range(10))
    assert make_specs(8, 5, seeds=2, sample_seed=11) == specs
    assert make_specs(8, 5, seeds=2, sample_seed=12) != specs


def test_all_pairs_or_too_many_past_six_blocks_are_refused_naming_the_count():
    with pytest.raises(CsqlError, match="483,604,108,472 ordered start/goal pairs"):
        make_specs(8, "all")
    with pytest.raises(CsqlError, match=f"7 blocks have {pair_count(7):,} ordered start/goal pairs"):
        make_specs(7, pair_count(7) + 1)


def test_only_lifted_policies_plan_past_six_blocks(tmp_path):
    with pytest.raises(CsqlError, match="BFS enumerates"):
        PolicyData.read(None, 8)
    ground = save(tmp_path / "r3.yaml", RuleBase(3, list(r_classifiers(3))))
    with pytest.raises(CsqlError, match="3 blocks"):
        PolicyData.read(ground, 8)
    with pytest.raises(CsqlError, match="not both"):
        PolicyData.read(ground, 8, named="gn1")
    assert isinstance(PolicyData.read(None, 8, named="gn1").policy(), Gn1Policy)
    with pytest.raises(CsqlError, match="at most 30 cubes"):
        evaluate(n=31, pairs=1, planner="gn1", progress=False)


def test_an_evaluation_of_seven_cubes_reports_the_exact_optimum(tmp_path):
    report = evaluate(n=7, pairs=2, planner="gn1", workers=1, progress=False, seed=4)
    assert report.episodes == 2 and report.success_rate == 1.0, report.failures
    for run, (start, goal) in zip(report.runs, sample_pairs(7, 2, np.random.default_rng(4)), strict=True):
        assert (run.start, run.goal) == (start.notation(), goal.notation())
        assert run.optimal_length == optimal_length(start, goal)
        assert run.length >= run.optimal_length
    assert report.config["blocks"] == 7 and report.config["planner"] == "gn1"


def test_cli_evaluate_of_eight_cubes_with_gn1(tmp_path, capsys):
    out = tmp_path / "e.json"
    assert main(["evaluate", "--blocks", "8", "--pairs", "1", "--planner", "gn1", "--seed", "2", "--workers", "1",
                 "--quiet", "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    (start, goal), = sample_pairs(8, 1, np.random.default_rng(2))
    assert doc["runs"][0]["start"] == start.notation() and doc["runs"][0]["success"]
    assert doc["runs"][0]["optimal_length"] == optimal_length(start, goal)


@pytest.mark.parametrize("argv, names", [
    (["evaluate", "--blocks", "31", "--pairs", "2", "--planner", "gn1"], "at most 30 cubes"),
    (["evaluate", "--blocks", "8", "--pairs", "all", "--planner", "gn1"], "483,604,108,472 ordered start/goal pairs"),
    (["evaluate", "--blocks", "8", "--pairs", "2"], "BFS enumerates"),
    (["render", "--start", ", ".join(default_names(31)), "--goal", " ".join(default_names(31)), "--planner", "gn1"],
     "at most 30 cubes"),
    (["render", "--start", "A,B,C,D,E,F,G", "--goal", "GFEDCBA"], "BFS enumerates"),
])
def test_cli_refusals_past_the_arm_or_the_enumerated_world(tmp_path, capsys, monkeypatch, argv, names):
    monkeypatch.chdir(tmp_path)
    try:
        code = main(argv + ["--quiet"])
    except SystemExit as exc:  # a usage error: argparse's one line
        code = exc.code
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and err.count("\n") == 1 and "Traceback" not in err, err
    assert names in err
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_render_a_seven_cube_episode(tmp_path):
    start, goal = parse_config("A,B,C,D,E,F,G"), parse_config("A,B,C,D,E,GF")
    result, path = render_episode(start, goal, tmp_path / "v.gif", Gn1Policy(), width=96, height=72, fps=5,
                                  workers=1, progress=False, renderer="tiny")
    assert result.success and path.stat().st_size > 1000
    sidecar = json.loads((tmp_path / "v.gif.json").read_text())
    assert sidecar["video"]["actions"] == 2 and sidecar["parameters"]["start"] == "A,B,C,D,E,F,G"
    assert isinstance(parse_config(sidecar["parameters"]["goal"]), State)


def test_execute_a_task_of_eight_cubes_with_gn1():
    result = execute_task("A,B,C,D,E,F,G,H", "HGFEDCBA", planner="gn1")
    assert result.reached and result.final == "HGFEDCBA", result.explain()
    assert [s.status for s in result.steps] == ["ok"] * 14
    assert _replay(parse_config("A,B,C,D,E,F,G,H"), [s.action for s in result.steps]) == parse_config("HGFEDCBA")
    doc = result.to_dict()
    assert doc["objects"]["h"] == "H" and "(on g h)" in doc["goal"]["atoms"] and doc["blocks"] == 8


@pytest.mark.parametrize("kwargs, names", [
    ({"planner": "bfs"}, "BFS enumerates"),
    ({"plan": ["(stack a b)"], "planner": None}, r"plan line 1: step 1 \(stack a b\) = stack\(A,B\) is not "
                                                 r"applicable in A,B,C,D,E,F,G,H: a is not held"),
    ({"planner": "gn1", "start": ", ".join(default_names(31)), "goal": " ".join(default_names(31))},
     "at most 30 cubes"),
])
def test_execute_past_six_blocks_refuses_bfs_a_wrong_plan_and_31_cubes(kwargs, names):
    task = {"start": "A,B,C,D,E,F,G,H", "goal": "HGFEDCBA", **kwargs}
    with pytest.raises(CsqlError, match=names):
        execute_task(**task)


def _replay(start, names):
    state = start
    for name in names:
        state = next(successor(state, a) for a in legal_actions(state) if action_name(a) == name)
    return state


def test_a_lifted_rule_file_is_read_once_and_shipped_to_the_workers(tmp_path, monkeypatch):
    import pickle

    import csql_sim.jobs.evaluate as evaluation

    rules = tmp_path / "lifted.json"
    rules.write_text("{}")
    reads = []

    def lifted_policy(path, n, progress=False):  # what load_policy returns for a lifted file: blocks None
        reads.append((path, n))
        return Gn1Policy()

    monkeypatch.setattr(evaluation, "load_policy", lifted_policy)
    data = PolicyData.read(rules, 8)
    assert reads == [(rules, 8)] and isinstance(pickle.loads(pickle.dumps(data)).policy(), Gn1Policy)
    report = evaluate(n=7, pairs=1, rules=str(rules), workers=1, progress=False, seed=1)
    assert report.success_rate == 1.0 and report.config["rules"]["sha256"]


@pytest.mark.parametrize("source", [["--planner", "gn1"], ["--rules", "builtin"]])
def test_cli_evaluate_of_eleven_cubes_with_gn1_and_the_lifted_rules(tmp_path, source):
    """Past ten cubes (the ring): a pair drawn by counting reaches its goal (success is perceived), optimally."""
    out = tmp_path / "e.json"
    assert main(["evaluate", "--blocks", "11", "--pairs", "1", *source, "--seed", "6", "--workers", "1",
                 "--quiet", "--json", str(out)]) == 0
    run, = json.loads(out.read_text())["runs"]
    (start, goal), = sample_pairs(11, 1, np.random.default_rng(6))
    assert run["start"] == start.notation() and run["goal"] == goal.notation() and run["success"]
    assert run["reason"] == "" and run["length"] == run["optimal_length"] == optimal_length(start, goal) >= 17
