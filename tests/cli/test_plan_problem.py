"""``plan --problem`` / ``--problems``: PDDL problems of any size, in the problem's own words."""

import json
import re
from pathlib import Path

import pytest

from csql_sim.cli import main
from csql_sim.core.files.ipc_plan import check_plan, read_plan
from csql_sim.core.files.pddl_import import read_problem
from csql_sim.jobs.problems import drawn_problems

SHIPPED = Path(__file__).resolve().parents[2] / "assets" / "rules" / "lifted.json"
MOVE_DOMAIN = """(define (domain blocksworld)
  (:requirements :strips :equality :negative-preconditions)
  (:predicates (clear ?x) (on-table ?x) (on ?x ?y))
  (:action move-b-to-b :parameters (?bm ?bf ?bt)
    :precondition (and (clear ?bm) (clear ?bt) (on ?bm ?bf) (not (= ?bm ?bt)))
    :effect (and (not (clear ?bt)) (not (on ?bm ?bf)) (on ?bm ?bt) (clear ?bf)))
  (:action move-b-to-t :parameters (?bm ?bf)
    :precondition (and (clear ?bm) (on ?bm ?bf))
    :effect (and (not (on ?bm ?bf)) (on-table ?bm) (clear ?bf)))
  (:action move-t-to-b :parameters (?bm ?bt)
    :precondition (and (clear ?bm) (clear ?bt) (on-table ?bm) (not (= ?bm ?bt)))
    :effect (and (not (clear ?bt)) (not (on-table ?bm)) (on ?bm ?bt))))
"""
PICKUP_DOMAIN = """(define (domain bw)
  (:predicates (on ?x ?y) (ontable ?x) (clear ?x) (handempty) (holding ?x))
  (:action pickup :parameters (?x) :precondition (and (clear ?x) (ontable ?x) (handempty))
    :effect (and (not (ontable ?x)) (not (clear ?x)) (not (handempty)) (holding ?x)))
  (:action putdown :parameters (?x) :precondition (holding ?x)
    :effect (and (not (holding ?x)) (clear ?x) (handempty) (ontable ?x)))
  (:action stack :parameters (?x ?y) :precondition (and (holding ?x) (clear ?y))
    :effect (and (not (holding ?x)) (not (clear ?y)) (clear ?x) (handempty) (on ?x ?y)))
  (:action unstack :parameters (?x ?y) :precondition (and (on ?x ?y) (clear ?x) (handempty))
    :effect (and (holding ?x) (clear ?y) (not (clear ?x)) (not (handempty)) (not (on ?x ?y)))))
"""


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def generated(tmp_path, n, count=1, seed=4):
    """A folder of ``count`` tall-tower problems of n blocks (b1..bN) and their domain; their paths."""
    files = drawn_problems("tall-towers", [n], count, seed=seed)
    for name, text in files:
        (tmp_path / name).write_text(text)
    return tmp_path / files[0][0], [tmp_path / name for name, _ in files[1:]]


def replayed(problem, plan, domain=None):
    """Read a plan file back against its problem (and the domain's action names); the end state."""
    bp = read_problem(problem, domain, max_blocks=2000)
    steps = read_plan(plan, bp.index, bp.n, allowed=bp.actions)
    end = check_plan(bp.start, steps)[-1]
    return bp, steps, end


def test_a_generated_problem_is_planned_and_its_plan_file_read_back(capsys, tmp_path):
    domain, (problem,) = generated(tmp_path, 40)
    code, out, err = run(capsys, "plan", "--problem", problem, "--domain", domain, "--rules", SHIPPED,
                         "--plan-out", tmp_path / "p.plan", "--json", "--optimum-budget", "0.2")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["solved"] and doc["blocks"] == 40 and doc["cost"] == len(doc["plan"]) >= doc["lower_bound"] > 0
    assert doc["plan"][0]["message"] is None and re.fullmatch(r"\([a-z-]+ b\d+( b\d+)?\)", doc["plan"][0]["name"])
    text = (tmp_path / "p.plan").read_text()
    assert re.search(r"^\((pick-up|unstack) b\d+", text, re.M) and f"; cost = {doc['cost']}" in text
    bp, steps, end = replayed(problem, tmp_path / "p.plan", domain)
    assert bp.goal.satisfied(end) and len(steps) == doc["cost"]
    assert doc["optimum"]["lower"] <= doc["cost"] and doc["optimum"]["upper"] <= doc["cost"]


def test_the_domain_names_the_actions_and_a_partial_goal_leaves_free_blocks_standing(capsys, tmp_path):
    objects = [f"x{i}" for i in range(1, 31)]  # x1..x30 on the table; x30 on x29; the goal names three blocks
    init = " ".join(f"(ontable {o})" for o in objects[:29]) + " (on x30 x29)"
    clear = " ".join(f"(clear {o})" for o in objects[:28] + ["x30"])
    (tmp_path / "d.pddl").write_text(PICKUP_DOMAIN)
    (tmp_path / "p.pddl").write_text(f"(define (problem part) (:domain bw) (:objects {' '.join(objects)}) "
                                     f"(:init {init} {clear} (handempty)) (:goal (and (on x1 x2) (on x2 x3))))")
    code, out, err = run(capsys, "plan", "--problem", tmp_path / "p.pddl", "--domain", tmp_path / "d.pddl",
                         "--planner", "gn1", "--plan-out", tmp_path / "p.plan")
    assert code == 0, err
    lines = [x for x in (tmp_path / "p.plan").read_text().splitlines() if not x.startswith(";")]
    assert lines == ["(pickup x2)", "(stack x2 x3)", "(pickup x1)", "(stack x1 x2)"]  # x30 stays on x29
    bp, _, end = replayed(tmp_path / "p.pddl", tmp_path / "p.plan", tmp_path / "d.pddl")
    assert bp.goal.partial and bp.goal.satisfied(end) and end.support[29] == 28
    assert "4 actions by gn1" in out and "optimum 4 (proven)" in out


@pytest.mark.parametrize("one_operator", [False, True])
def test_a_move_domain_gets_one_move_per_pick_and_put(capsys, tmp_path, one_operator):
    objects = [f"c{i}" for i in range(1, 9)]  # c1..c8 one tower c1 at the bottom; goal: the reverse
    tower = " ".join(f"(on {objects[i + 1]} {objects[i]})" for i in range(7))
    goal = " ".join(f"(on {objects[i]} {objects[i + 1]})" for i in range(7))
    table = "(:requirements :typing) (:objects table - table c1 c2 c3 c4 c5 c6 c7 c8 - block)" if one_operator else \
        f"(:objects {' '.join(objects)})"
    (tmp_path / "p.pddl").write_text(f"(define (problem rev) (:domain blocksworld) {table} "
                                     f"(:init (on-table c1) {tower} (clear c8)) (:goal (and {goal})))")
    domain = []
    if not one_operator:
        (tmp_path / "d.pddl").write_text(MOVE_DOMAIN)
        domain = ["--domain", tmp_path / "d.pddl"]
    code, _, err = run(capsys, "plan", "--problem", tmp_path / "p.pddl", *domain, "--planner", "gn1",
                       "--plan-out", tmp_path / "p.plan")
    assert code == 0, err
    lines = [x for x in (tmp_path / "p.plan").read_text().splitlines() if not x.startswith(";")]
    if one_operator:
        assert lines[0] == "(move c8 c7 table)" and lines[-1] == "(move c1 table c2)"
        assert all(x.startswith("(move c") for x in lines)
    else:
        assert lines[0] == "(move-b-to-t c8 c7)" and lines[1] == "(move-b-to-b c7 c6 c8)"
        assert lines[-1] == "(move-t-to-b c1 c2)"
    bp, steps, end = replayed(tmp_path / "p.pddl", tmp_path / "p.plan", tmp_path / "d.pddl" if domain else None)
    assert bp.style == "move" and bp.goal.satisfied(end) and len(steps) == len(lines) == 8  # 8 moves, 16 actions


def test_a_domain_that_is_not_the_blocks_world_is_refused(capsys, tmp_path):
    (tmp_path / "d.pddl").write_text("(define (domain air) (:predicates (at ?x)) (:action fly :parameters (?x) "
                                     ":precondition (at ?x) :effect (not (at ?x))))")
    _, (problem,) = generated(tmp_path, 8)
    code, out, err = run(capsys, "plan", "--problem", problem, "--domain", tmp_path / "d.pddl", "--planner", "gn1")
    assert code == 2 and out == "" and err.count("\n") == 1 and "fly/1" in err and "Traceback" not in err


@pytest.mark.parametrize("argv, names", [
    (["--problem", "x.pddl", "--problems", "."], "not both"),
    (["--problem", "x.pddl", "--start", "AB"], "--start"),
    (["--problems", ".", "--plan-out", "."], "--plan-out '.' is the folder of the problems"),
    (["--domain", "d.pddl", "--start", "AB", "--goal", "BA"], "--domain goes with"),
])
def test_bad_options_exit_2_in_one_line(capsys, argv, names):
    code, out, err = run(capsys, "plan", *argv)
    assert code == 2 and out == "" and names in err and "Traceback" not in err
    with pytest.raises(SystemExit) as caught:
        main(["plan", "--problem", "x.pddl", "--optimum-budget", "-1"])
    assert caught.value.code == 2 and "--optimum-budget: must be a number of seconds >= 0" in capsys.readouterr().err


def test_bfs_is_refused_past_six_blocks(capsys, tmp_path):
    _, (problem,) = generated(tmp_path, 9)
    code, out, err = run(capsys, "plan", "--problem", problem, "--planner", "bfs")
    assert code == 2 and out == "" and "plans only up to 6 blocks" in err


@pytest.mark.parametrize("n", [4, 30])
def test_without_a_planner_a_problem_plans_with_the_shipped_lifted_rules(capsys, tmp_path, n):
    domain, (problem,) = generated(tmp_path, n)
    code, out, err = run(capsys, "plan", "--problem", problem, "--plan-out", tmp_path / "p.plan", "--json",
                         "--optimum-budget", "0")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["planner"] == "rules" and doc["solved"] and doc["cost"] >= doc["lower_bound"]
    bp, steps, end = replayed(problem, tmp_path / "p.plan", domain)
    assert bp.goal.satisfied(end) and len(steps) == doc["cost"]


def test_builtin_names_the_shipped_rules_wherever_rules_are_taken(capsys, tmp_path):
    domain, (problem,) = generated(tmp_path, 9)
    code, out, err = run(capsys, "plan", "--problem", problem, "--rules", "builtin", "--optimum-budget", "0")
    assert code == 0 and "by rules" in out, err
    code, out, err = run(capsys, "plan", "--start", "CBA", "--goal", "ABC", "--rules", "builtin", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["length"] >= doc["optimal_length"] == 6, err  # reverse a tower of 3: 6 at best
    code, out, err = run(capsys, "show", "--rules", "builtin")
    assert code == 0 and out.strip(), err


def test_a_folder_gives_one_row_per_task_and_a_failed_row_for_a_broken_file(capsys, tmp_path):
    generated(tmp_path, 12, count=2)
    (tmp_path / "zz-broken.pddl").write_text("(define (problem broken")
    code, out, err = run(capsys, "plan", "--problems", tmp_path, "--planner", "gn1", "--json",
                         "--optimum-budget", "0")
    assert code == 1, err
    doc = json.loads(out)
    rows = {Path(r["problem"]).name: r for r in doc["rows"]}
    assert doc["problems"] == 3 and doc["solved"] == 2 and set(rows) == {
        "tall-towers-12-01.pddl", "tall-towers-12-02.pddl", "zz-broken.pddl"}
    broken = rows.pop("zz-broken.pddl")
    assert not broken["solved"] and "zz-broken.pddl" in broken["reason"] and broken["cost"] is None
    for row in rows.values():
        assert row["solved"] and row["cost"] >= row["lower_bound"] and row["optimum"] is None
    code, out, _ = run(capsys, "plan", "--problems", tmp_path, "--planner", "gn1", "--optimum-budget", "0")
    assert code == 1 and "2/3 problems solved" in out and "FAILED: " in out and "not measured" in out
    (tmp_path / "zz-broken.pddl").unlink()
    code, out, _ = run(capsys, "plan", "--problems", tmp_path, "--planner", "gn1", "--optimum-budget", "0.1")
    assert code == 0 and "2/2 problems solved" in out


def test_an_unsolved_task_exits_1_and_is_a_failed_row(capsys, tmp_path):
    doc = json.loads(SHIPPED.read_text())
    doc["classifiers"] = ["Q 01####### move(?x,?d)->block  advantage=1.000 error=0.000 experience=100"]  # never matches
    (tmp_path / "rules").mkdir()
    (tmp_path / "rules" / "none.json").write_text(json.dumps(doc))
    _, (problem,) = generated(tmp_path, 12)
    code, out, err = run(capsys, "plan", "--problem", problem, "--rules", tmp_path / "rules" / "none.json")
    assert code == 1 and out == "" and "not solved by rules: no action" in err and err.count("\n") == 1
    code, out, _ = run(capsys, "plan", "--problems", tmp_path, "--rules", tmp_path / "rules" / "none.json", "--json")
    row = json.loads(out)["rows"][0]
    assert code == 1 and not row["solved"] and row["cost"] is None and row["reason"].startswith("no action")


def test_csql_sims_own_export_is_planned_in_its_own_words(capsys, tmp_path):
    assert run(capsys, "pddl", "--start", "CBA", "--goal", "BAC", "--out", tmp_path / "task")[0] == 0
    task = tmp_path / "task"
    code, out, err = run(capsys, "plan", "--problem", task / "problem.pddl", "--domain", task / "domain.pddl",
                         "--plan-out", tmp_path / "p.plan", "--planner", "bfs")
    assert code == 0, err
    assert out.splitlines()[0] == "(unstack_a_b)" and "8 actions by bfs" in out and "optimum 8 (proven)" in out
    bp, steps, end = replayed(task / "problem.pddl", tmp_path / "p.plan", task / "domain.pddl")
    assert bp.style == "csql" and bp.goal.satisfied(end) and len(steps) == 8


def test_the_pddl_options_are_parameters_of_pddl_jobs_only(capsys, tmp_path):
    code, out, _ = run(capsys, "plan", "--start", "CBA", "--goal", "BAC", "--json")
    parameters = json.loads(out)["provenance"]["parameters"]
    assert code == 0 and parameters["start"] == "CBA"
    assert not {"problem", "problems", "domain", "optimum_budget"} & set(parameters)
    _, (problem,) = generated(tmp_path, 8)
    code, out, _ = run(capsys, "plan", "--problem", problem, "--planner", "gn1", "--json")
    parameters = json.loads(out)["provenance"]["parameters"]
    assert code == 0 and parameters["problem"] == str(problem) and parameters["optimum_budget"] == 1.0


def test_plan_out_with_a_folder_writes_the_plan_files_evaluate_reads(capsys, tmp_path):
    from csql_sim.jobs.execute_batch import plan_file

    problems, plans = tmp_path / "problems", tmp_path / "plans"
    problems.mkdir()
    domain, tasks = generated(problems, 9, count=3)
    code, out, err = run(capsys, "plan", "--problems", problems, "--plan-out", plans, "--optimum-budget", "0")
    assert code == 0 and "wrote 3 plan file(s)" in out, err
    assert sorted(p.name for p in plans.iterdir()) == [t.stem + ".plan" for t in tasks]
    for task in tasks:
        bp, steps, end = replayed(task, plan_file(task, plans), domain)  # the file evaluate --plans would read
        assert bp.goal.satisfied(end) and steps
    before = {p.name: p.read_text() for p in plans.iterdir()}
    code, out, err = run(capsys, "plan", "--problems", problems, "--plan-out", plans)
    assert code == 2 and out == "" and err.count("\n") == 1 and "--overwrite" in err
    assert {p.name: p.read_text() for p in plans.iterdir()} == before
    code, out, err = run(capsys, "plan", "--problems", problems, "--plan-out", plans, "--overwrite",
                         "--optimum-budget", "0")
    assert code == 0, err
    code, out, err = run(capsys, "plan", "--problems", problems, "--plan-out", problems)
    assert code == 2 and "is the folder of the problems" in err and sorted(problems.iterdir()) == sorted(
        [domain, *tasks])


@pytest.mark.parametrize("init, message", [
    ("(on b1 b1) (ontable b2) (clear b2)", "block b1 stands on itself"),
    ("(ontable b1) (on b2 b1) (on b3 b1) (clear b2) (clear b3)", "two blocks stand on block b1"),
])
def test_a_broken_initial_state_is_named_in_the_problems_words(capsys, tmp_path, init, message):
    objects = " ".join(sorted({w for w in init.replace("(", " ").replace(")", " ").split() if w.startswith("b")}))
    problem = tmp_path / "p.pddl"
    problem.write_text(f"(define (problem p) (:domain blocks) (:objects {objects}) "
                       f"(:init (handempty) {init}) (:goal (and (ontable b1))))")
    code, out, err = run(capsys, "plan", "--problem", problem, "--planner", "gn1")
    assert code == 2 and out == "" and err.count("\n") == 1 and message in err
