"""The execute job: outside plans (Fast Downward, pyperplan) on the simulated arm, closed loop."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from csql_sim.cli import OneLineParser
from csql_sim.cli import execute as execute_cli
from csql_sim.cli.output import plan_outputs
from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.files.ipc_plan import PlanError
from csql_sim.core.files.pddl_export import domain_text as export_domain_text
from csql_sim.core.files.pddl_export import problem_text as export_problem_text
from csql_sim.core.model.search import bfs_plan
from csql_sim.core.state.notation import parse_config
from csql_sim.infra.errors import CsqlError
from csql_sim.jobs.execute import execute_problem, execute_task
from csql_sim.jobs.problems import DOMAIN_TEXT, generate_problem, task_problem_text

DATA = Path(__file__).resolve().parents[1] / "data" / "problems"
MOVE3_DOMAIN = """(define (domain blocksworld) (:requirements :strips)
(:predicates (clear ?x) (on-table ?x) (on ?x ?y))
(:action move-b-to-b :parameters (?bm ?bf ?bt) :precondition (and (clear ?bm) (clear ?bt) (on ?bm ?bf))
  :effect (and (not (clear ?bt)) (not (on ?bm ?bf)) (on ?bm ?bt) (clear ?bf)))
(:action move-b-to-t :parameters (?bm ?bf) :precondition (and (clear ?bm) (on ?bm ?bf))
  :effect (and (not (on ?bm ?bf)) (on-table ?bm) (clear ?bf)))
(:action move-t-to-b :parameters (?bm ?bt) :precondition (and (clear ?bm) (clear ?bt) (on-table ?bm))
  :effect (and (not (clear ?bt)) (not (on-table ?bm)) (on ?bm ?bt))))
"""


def cli(argv: list[str]) -> int:
    """What ``csql-sim execute ...`` does once the subcommand is wired into csql_sim.cli.main."""
    parser = OneLineParser(prog="csql-sim")
    execute_cli.register(parser.add_subparsers(dest="command", required=True, parser_class=OneLineParser))
    args = parser.parse_args(argv)
    try:
        plan_outputs(args)
        return int(args.func(args))
    except CsqlError as exc:
        print(f"csql-sim: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


@pytest.mark.parametrize("name", ["blocks3-02", "blocks5-02"])
def test_a_fast_downward_style_plan_reaches_the_goal(name):
    result = execute_problem(DATA / f"{name}.pddl", DATA / "domain.pddl", plan=DATA / f"{name}.plan")
    plan_lines = [line for line in (DATA / f"{name}.plan").read_text().splitlines() if not line.startswith(";")]
    assert result.reached and result.reason == "" and result.final == result.target
    assert [s.line for s in result.steps] == list(range(1, len(plan_lines) + 1))
    assert [s.text for s in result.steps] == plan_lines
    assert all(s.status == "ok" and s.perceived == s.expected for s in result.steps)
    report = result.to_dict()
    assert (report["format"], report["version"], report["reached"]) == ("csql-sim execute report", 1, True)
    assert report["objects"] == {c: c.upper() for c in "abcde"[: result.blocks]}
    assert report["provenance"]["parameters"]["plan"]["file"].endswith(f"{name}.plan")
    assert json.loads(json.dumps(report)) == report


def test_a_wrong_step_is_refused_before_physics_with_its_line(tmp_path, monkeypatch, capsys):
    import csql_sim.sim.control as executor

    def no_physics(*args, **kwargs):
        raise AssertionError("physics ran")

    monkeypatch.setattr(executor, "run_physical_episode", no_physics)
    plan = write(tmp_path / "bad.plan", "; from a planner\n(unstack c b)\n(put-down c)\n(stack b a)\n")
    with pytest.raises(PlanError) as caught:
        execute_problem(DATA / "blocks3-02.pddl", plan=plan)
    assert "bad.plan line 4: step 3 (stack b a) is not applicable in a,b,c: b is not held" \
        in str(caught.value)  # in the problem's names
    assert cli(["execute", "--problem", str(DATA / "blocks3-02.pddl"), "--plan", str(plan)]) == 2
    err = capsys.readouterr().err
    assert "line 4" in err and err.count("\n") == 1


def test_the_three_operator_move_variant(tmp_path):
    domain = write(tmp_path / "domain.pddl", MOVE3_DOMAIN)
    problem = write(tmp_path / "p.pddl", "(define (problem bw) (:domain blocksworld) (:objects B1 B2 B3)\n"
                    "(:init (on-table B1) (on B2 B1) (on B3 B2) (clear B3))\n(:goal (and (on B1 B2) (on B2 B3))))\n")
    plan = write(tmp_path / "p.plan", "(move-b-to-t b3 b2)\n(move-b-to-b b2 b1 b3)\n(move-t-to-b b1 b2)\n"
                                      "; cost = 3 (unit cost)\n")
    result = execute_problem(problem, domain, plan=plan)
    assert result.reached and result.mapping == {"b1": "A", "b2": "B", "b3": "C"} and result.final == "CBA"
    assert [(s.line, s.action) for s in result.steps] == [
        (1, "unstack(C,B)"), (1, "putdown(C)"), (2, "unstack(B,A)"), (2, "stack(B,C)"), (3, "pickup(A)"),
        (3, "stack(A,B)")]
    with pytest.raises(PlanError, match="line 1: pick-up is not an action of the domain"):
        execute_problem(problem, domain, plan=write(tmp_path / "q.plan", "(pick-up b3)\n"))


def test_the_one_operator_move_variant_with_a_table_object(tmp_path):
    problem = write(tmp_path / "p.pddl", "(define (problem q) (:domain bw) (:objects a b c table)\n"
                    "(:init (on a table) (on b table) (on c a) (clear b) (clear c) (clear table))\n"
                    "(:goal (and (on a b) (on b c))))\n")
    result = execute_problem(problem, plan=["(move c a table)", "(move b table c)", "(move a table b)"])
    assert result.reached and result.final == "CBA"
    assert [s.action for s in result.steps] == ["unstack(C,A)", "putdown(C)", "pickup(B)", "stack(B,C)",
                                                "pickup(A)", "stack(A,B)"]


def test_a_partial_goal_is_reached_by_any_state_satisfying_it(tmp_path):
    problem = write(tmp_path / "p.pddl", "(define (problem part) (:domain blocks) (:objects a b c)\n"
                    "(:init (handempty) (ontable c) (on b c) (on a b) (clear a))\n(:goal (on c a)))\n")
    plan = write(tmp_path / "p.plan", "(unstack a b)\n(put-down a)\n(unstack b c)\n(put-down b)\n(pick-up c)\n"
                                      "(stack c a)\n")
    by_plan = execute_problem(problem, plan=plan)
    assert by_plan.reached and by_plan.goal.partial and by_plan.final == "AC,B"
    by_bfs = execute_problem(problem, planner="bfs")
    assert by_bfs.reached and by_bfs.target == by_bfs.final == "AC,B" and len(by_bfs.steps) == 6
    # four states have C on A: AC,B AC+B ACB BAC; the nearest is AC,B
    assert by_bfs.to_dict()["goal"] == {"atoms": ["(on c a)"], "partial": True, "states": 4, "target": "AC,B"}


def test_pyperplans_plans_execute(tmp_path):
    planner = pytest.importorskip("pyperplan.planner")
    domain = write(tmp_path / "domain.pddl", DOMAIN_TEXT)
    problem = write(tmp_path / "p.pddl", generate_problem(4, np.random.default_rng(3), "random4"))
    plan = planner.search_plan(str(domain), str(problem), planner.SEARCHES["bfs"], None)
    planner.write_solution(plan, str(tmp_path / "p.soln"))
    assert execute_problem(problem, domain, plan=tmp_path / "p.soln").reached
    # csql-sim's own export (`csql-sim pddl`): message facts and actions such as unstack_a_b
    start, goal = parse_config("CBA"), parse_config("BAC")
    domain = write(tmp_path / "export-domain.pddl", export_domain_text(r_classifiers(3), 3))
    problem = write(tmp_path / "export-problem.pddl", export_problem_text(r_classifiers(3), start, goal))
    plan = planner.search_plan(str(domain), str(problem), planner.SEARCHES["bfs"], None)
    planner.write_solution(plan, str(tmp_path / "export.soln"))
    result = execute_problem(problem, domain, plan=tmp_path / "export.soln")
    assert result.reached and len(result.steps) == 8 and result.final == "BAC"


def test_a_rule_base_drives_the_arm(tmp_path):
    from csql_sim.core.files.rulebase import save
    from csql_sim.learners.training.tabular import train

    rules = tmp_path / "rules.yaml"
    save(rules, train("cs-ql", trials=2500, seed=0))
    problem = write(tmp_path / "p.pddl", task_problem_text(parse_config("CBA"), parse_config("BAC")))
    result = execute_problem(problem, rules=rules)
    assert result.reached and result.source == {"kind": "rules", "file": str(rules)} and len(result.steps) == 8
    with pytest.raises(CsqlError, match="exactly one of"):
        execute_problem(problem, rules=rules, planner="bfs")


def test_perception_diverging_from_the_plan_stops_the_run():
    plan = [a.name() for a in bfs_plan(parse_config("CBA"), parse_config("BAC"))]
    result = execute_task("CBA", "BAC", plan=plan, seed=1, perturb=True)  # a nudge knocks A off B after step 7
    assert not result.reached and result.episode.events == ["nudged A towards -147 deg"]
    bad = result.failed_step
    assert (bad.step, bad.action, bad.status, bad.expected, bad.perceived) == (7, "pickup(C)", "diverged", "BA+C",
                                                                               "A,B+C")
    assert [s.status for s in result.steps[7:]] == ["not run"]
    assert result.reason == ("perception diverged from the plan after step 7 (line 7: pickup(C)): the plan "
                             "predicts BA+C, perceived A,B+C")
    assert "goal atoms not satisfied by the perceived state A,B+C: (handempty) (on a b) (on c a)" in result.explain()


def test_the_command_reports_json_and_exit_status(tmp_path, capsys):
    problem = str(DATA / "blocks3-01.pddl")
    out = tmp_path / "report.json"
    assert cli(["execute", "--problem", problem, "--plan", str(DATA / "blocks3-01.plan"), "--json", str(out)]) == 0
    report = json.loads(out.read_text())
    assert report["format"] == "csql-sim execute report" and report["reached"] is True
    assert [(s["line"], s["action"], s["status"]) for s in report["steps"]] == [
        (1, "(unstack b a)", "ok"), (2, "(put-down b)", "ok")]
    assert report["provenance"]["parameters"]["problem"]["file"] == problem
    short = write(tmp_path / "short.plan", "(unstack b a)\n")
    assert cli(["execute", "--problem", problem, "--plan", str(short)]) == 1
    text = capsys.readouterr().out
    assert "objects: a -> A, b -> B, c -> C" in text and "NOT reached: the plan ended" in text
    assert "legend: a = red, b = green, c = blue" in text and report["legend"] == {"a": "red", "b": "green",
                                                                                   "c": "blue"}
    eight = write(tmp_path / "p8.pddl", generate_problem(8, np.random.default_rng(0)))
    assert cli(["execute", "--problem", str(eight), "--planner", "bfs"]) == 2
    err = capsys.readouterr().err
    assert "BFS enumerates the world and plans only up to 6 blocks" in err and err.count("\n") == 1


def test_the_command_writes_a_video_with_its_provenance(tmp_path, capsys):
    video = tmp_path / "run.mp4"
    assert cli(["execute", "--problem", str(DATA / "blocks3-01.pddl"), "--plan", str(DATA / "blocks3-01.plan"),
                "--video", str(video), "--quiet"]) == 0
    sidecar = json.loads((tmp_path / "run.mp4.json").read_text())
    assert video.stat().st_size > 0 and sidecar["video"]["actions"] == 2 and sidecar["video"]["success"] is True
    assert sidecar["parameters"]["command"] == "execute"
    assert sidecar["video"]["legend"] == {"a": "red", "b": "green", "c": "blue"}
    assert cli(["execute", "--problem", str(DATA / "blocks3-01.pddl"), "--planner", "bfs", "--video",
                str(tmp_path)]) == 2  # a folder is refused before any work


def test_execute_and_render_share_the_video_options_and_name_the_steps(tmp_path, capsys):
    """execute takes render's video options, render takes --problem, the steps are in the problem's names."""
    import imageio.v2 as imageio

    from csql_sim.cli import main

    problem = Path(__file__).resolve().parents[1] / "data" / "large" / "blocks8-names.pddl"
    out, report = tmp_path / "run.gif", tmp_path / "run.json"
    assert cli(["execute", "--problem", str(problem), "--planner", "gn1", "--out", str(out), "--json", str(report),
                "--fps", "6", "--speed", "8", "--width", "96", "--height", "72", "--renderer", "flat",
                "--quiet"]) == 0
    doc, sidecar = json.loads(report.read_text()), json.loads((tmp_path / "run.gif.json").read_text())
    assert {k: sidecar["parameters"][k] for k in ("fps", "speed", "width", "height", "renderer")} == {
        "fps": 6, "speed": 8.0, "width": 96, "height": 72, "renderer": "flat"}
    # 6 frames per video second at 8 simulated seconds each: 0.75 frames per simulated second, 2 s held
    assert abs(sidecar["video"]["frames"] - (0.75 * doc["sim_seconds"] + 12)) <= 3
    assert imageio.mimread(out)[0].shape == (72, 96, 3)
    steps = doc["steps"]
    assert steps[0]["action"].startswith("(") and steps[0]["cube_action"][0].islower()
    names = {"amber_1", "b2", "b10", "ivory", "jade", "ruby", "slate", "x-ray"}
    assert all(set(s["action"].strip("()").split()[1:]) <= names for s in steps)
    video = tmp_path / "render.gif"
    assert main(["render", "--problem", str(problem), "--out", str(video), "--fps", "4", "--speed", "16",
                 "--width", "64", "--height", "48", "--quiet"]) == 0
    assert json.loads((tmp_path / "render.gif.json").read_text())["video"]["legend"]["x-ray"] == "magenta"


def test_past_six_blocks_a_partial_goal_aims_at_a_fixed_target_and_stops_once_satisfied():
    from csql_sim.core.policies.gn1 import Gn1Policy
    from csql_sim.core.state.notation import parse_config
    from csql_sim.jobs.execute import GoalSetPolicy, task_problem

    bp = task_problem("ABC,DEF,GH", ["(on a e)", "(on e h)"])
    assert bp.n == 8 and bp.goal.partial and bp.goal.count is None
    target = bp.goal.nearest(bp.start)
    seen = []

    class Spy(Gn1Policy):
        def act(self, state, goal):
            seen.append(goal)
            return super().act(state, goal)

    policy = GoalSetPolicy(Spy(), bp.goal, target)
    assert policy.blocks is None  # not a ground table: the arm takes it past six blocks
    assert policy.act(bp.start, bp.start) is not None and seen == [target]
    done = parse_config("BC,D,F,GHEA")  # a goal state that is not the target
    assert bp.goal.satisfied(done) and done != target and policy.act(done, done) is None


def test_past_six_blocks_a_ground_rule_file_is_refused_before_physics(monkeypatch):
    import csql_sim.sim.control as executor

    monkeypatch.setattr(executor, "run_physical_episode", lambda *a, **k: pytest.fail("physics ran"))
    rules = Path(__file__).resolve().parents[2] / "assets" / "rules" / "blocks3.yaml"
    with pytest.raises(CsqlError, match="is for 3 blocks, not 8"):
        execute_task("A,B,C,D,E,F,G,H", ["(on a b)"], rules=rules)


# ------------------------------------------------------------------ past ten cubes: the ring (issue 54)
LARGE = DATA.parent / "large"
TWELVE, TWELVE_PLAN = LARGE / "blocks12-names.pddl", LARGE / "blocks12-names.plan"
LIFTED = Path(__file__).resolve().parents[2] / "assets" / "rules" / "lifted.json"
TWELVE_NAMES = {"amber_1", "b2", "b10", "ivory", "jade", "onyx", "pearl", "ruby", "slate", "topaz", "x-ray", "zircon"}


def test_a_plan_file_takes_twelve_named_cubes_to_a_partial_goal_and_films_it(tmp_path):
    import imageio.v2 as imageio

    from csql_sim.core.files.pddl_import import read_problem

    problem = read_problem(TWELVE, DATA / "domain.pddl")
    assert problem.n == 12 and problem.goal.partial and not problem.goal.satisfied(problem.start)
    out, report = tmp_path / "run.mp4", tmp_path / "run.json"
    assert cli(["execute", "--problem", str(TWELVE), "--domain", str(DATA / "domain.pddl"), "--plan", str(TWELVE_PLAN),
                "--out", str(out), "--json", str(report), "--renderer", "flat", "--width", "96", "--height", "72",
                "--fps", "6", "--speed", "8", "--workers", "1", "--quiet"]) == 0
    doc, sidecar = json.loads(report.read_text()), json.loads((tmp_path / "run.mp4.json").read_text())
    assert doc["reached"] and doc["blocks"] == 12 and doc["goal"]["partial"] is True
    assert problem.goal.satisfied(parse_config(doc["final"]))  # the perceived final state
    plan_lines = [line for line in TWELVE_PLAN.read_text().splitlines() if line and not line.startswith(";")]
    assert [s["action"] for s in doc["steps"]] == plan_lines and {s["status"] for s in doc["steps"]} == {"ok"}
    assert sidecar["parameters"]["objects"] == problem.mapping and set(sidecar["video"]["legend"]) == TWELVE_NAMES
    assert sidecar["video"]["success"] and imageio.get_reader(out).count_frames() == sidecar["video"]["frames"] > 10


@pytest.mark.parametrize("source", [{"rules": LIFTED}, {"planner": "gn1"}])
def test_lifted_rules_and_gn1_take_twelve_named_cubes_to_the_partial_goal(source):
    from csql_sim.core.files.pddl_import import read_problem

    problem = read_problem(TWELVE)
    result = execute_problem(TWELVE, **source)
    assert result.reached, result.explain()
    assert problem.goal.satisfied(parse_config(result.final)) and 6 <= len(result.steps) <= 8
    assert all(set(s.text.strip("()").split()[1:]) <= TWELVE_NAMES for s in result.steps)  # the problem's names


def _thirty_problem(n: int) -> str:
    cubes = " ".join(f"c{i}" for i in range(n))
    init = " ".join(f"(ontable c{i}) (clear c{i})" for i in range(n))
    return f"(define (problem ring{n}) (:domain blocks) (:objects {cubes}) (:init (handempty) {init}) " \
           f"(:goal (and (on c1 c0) (on c{n - 1} c{n - 2}))))"


@pytest.mark.parametrize("source", [{"plan": ["pickup(AD)", "stack(AD,AC)", "(pick-up c1)", "(stack c1 c0)"]},
                                    {"planner": "gn1"}])
def test_thirty_cubes_named_past_z_are_read_planned_and_reported_and_31_refused(tmp_path, capsys, source):
    """Problems were read up to 26 objects only, and actions past Z (``pickup(AD)``) were no actions."""
    path = tmp_path / "ring30.pddl"
    path.write_text(_thirty_problem(30))
    result = execute_problem(path, **source)
    assert result.reached, result.explain()
    final = parse_config(result.final, 30)
    assert final.support[29] == 28 and final.support[1] == 0  # (on c29 c28) (on c1 c0), as perceived
    if "planner" in source:  # the planner's steps, written in the problem's names
        assert {"(pick-up c29)", "(stack c29 c28)"} <= {s.text for s in result.steps}
    (tmp_path / "ring31.pddl").write_text(_thirty_problem(31))
    assert cli(["execute", "--problem", str(tmp_path / "ring31.pddl"), "--planner", "gn1", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "at most 30 cubes" in err
