"""The top-level API: plan, validate, execute and train_lifted in the problem's names (issue 52)."""

import doctest
import subprocess
import sys
from pathlib import Path

import pytest

import csql_sim
from csql_sim.api import planning, results, running
from csql_sim.core.model.search import distance
from csql_sim.infra.errors import CsqlError

ROOT = Path(__file__).resolve().parents[2]
PROBLEM = """(define (problem gems) (:domain blocks)
  (:objects Amber pearl coral jade)
  (:init (handempty) (ontable pearl) (on Amber pearl) (on coral Amber) (clear coral)
         (ontable jade) (clear jade))
  (:goal (and (on pearl coral) (on coral jade) (on jade Amber))))
"""


@pytest.mark.parametrize("module", [planning, running, results])
def test_the_docstring_examples_run(module):
    failed, tried = doctest.testmod(module, optionflags=doctest.ELLIPSIS, verbose=False)[:2]
    assert failed == 0
    assert tried > 0 or module is results


def test_every_function_is_on_the_api_page():
    page = (ROOT / "docs" / "api.md").read_text()
    for name in ("plan", "validate", "execute", "train_lifted"):
        assert f"::: csql_sim.api.{name}" in page
        assert "Example:" in getattr(csql_sim.api, name).__doc__
    assert "::: csql_sim.up_engine" in page


def test_import_csql_sim_is_lazy_and_plan_never_imports_the_simulator():
    code = ("import sys, csql_sim; assert not [m for m in sys.modules if m.startswith('csql_sim.')]; "
            f"p = csql_sim.plan({PROBLEM!r}); assert p.solved; "
            "assert 'pybullet' not in sys.modules, 'pybullet imported'; "
            "assert csql_sim.plan is csql_sim.api.plan and 'validate' in dir(csql_sim)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    with pytest.raises(AttributeError):
        csql_sim.no_such_name  # noqa: B018


def test_a_plan_is_in_the_problems_names_and_optimal_length_is_bfs(tmp_path):
    path = tmp_path / "gems.pddl"
    path.write_text(PROBLEM)
    from_file, from_text = csql_sim.plan(path), csql_sim.plan(PROBLEM)
    assert from_file == from_text and from_file.problem == "gems" and from_file.planner == "builtin"
    assert from_file.objects == ("Amber", "coral", "jade", "pearl")  # as the file spells them
    named = {word for action in from_file.actions for word in action[1:]}
    assert named <= set(from_file.objects) and "Amber" in named
    blocks = planning.read_blocks(PROBLEM)
    assert from_file.optimal_length == distance(blocks.start, blocks.goal.nearest(blocks.start))
    assert from_file.length >= from_file.optimal_length >= from_file.lower_bound
    bfs = csql_sim.plan(PROBLEM, planner="bfs")
    assert bfs.length == bfs.optimal_length == from_file.optimal_length
    assert csql_sim.validate(PROBLEM, bfs).valid and csql_sim.validate(PROBLEM, from_file).valid
    assert csql_sim.plan(PROBLEM, planner="gn1").solved and csql_sim.plan(PROBLEM, planner="gn2").solved


def test_the_default_rules_are_the_file_that_rules_builtin_names():
    from csql_sim.infra.assets import builtin_rules_path

    default, by_file = csql_sim.plan(PROBLEM), csql_sim.plan(PROBLEM, rules=builtin_rules_path())
    assert default.actions == by_file.actions == csql_sim.plan(PROBLEM, rules="builtin").actions
    assert (default.planner, by_file.planner) == ("builtin", "rules")


def test_a_plan_written_reads_back_and_validates(tmp_path):
    plan = csql_sim.plan(PROBLEM)
    written = plan.write(tmp_path / "gems.plan")
    assert written.read_text().splitlines()[: plan.length] == list(plan.lines)
    verdict = csql_sim.validate(PROBLEM, written)
    assert verdict.valid and verdict.steps == plan.length and verdict.errors == ()
    with pytest.raises(CsqlError, match="exists"):
        plan.write(written)
    assert plan.write(written, overwrite=True) == written


def test_past_six_blocks_the_optimum_is_measured_within_a_budget():
    text = ("(define (problem eight) (:domain blocks) (:objects b1 b2 b3 b4 b5 b6 b7 b8) (:init (handempty) "
            "(ontable b1) (on b2 b1) (on b3 b2) (on b4 b3) (clear b4) (ontable b5) (on b6 b5) (on b7 b6) (on b8 b7) "
            "(clear b8)) (:goal (and (on b1 b5) (on b5 b2) (on b2 b6) (on b6 b3) (on b3 b7) (on b7 b4) (on b4 b8))))")
    plain = csql_sim.plan(text)
    assert plain.solved and len(plain.objects) == 8 and plain.optimal_length is None
    measured = csql_sim.plan(text, optimum_budget=5.0)
    assert measured.actions == plain.actions
    assert measured.optimal_length is None or measured.lower_bound <= measured.optimal_length <= measured.length


def test_validate_names_the_failing_step_and_the_missing_goal():
    plan = csql_sim.plan(PROBLEM)
    swapped = [plan.actions[1], plan.actions[0], *plan.actions[2:]]
    verdict = csql_sim.validate(PROBLEM, swapped)
    assert not verdict.valid and len(verdict.errors) == 1 and "step 1" in verdict.errors[0]
    short = csql_sim.validate(PROBLEM, plan.actions[:-1])
    assert not short.valid and "(on pearl coral)" in short.errors[0] and short.steps == plan.length - 1
    assert short.errors == tuple(f"goal {atom} does not hold after step {plan.length - 1}"
                                 for atom in planning.read_blocks(PROBLEM).goal.unsatisfied(
                                     short.report.end))  # one line per goal atom missed, as `csql-sim validate`
    assert not bool(short) and bool(csql_sim.validate(PROBLEM, plan.text()))


def test_a_plan_line_that_is_no_action_of_the_problem_is_bad_input_as_in_the_validate_command():
    with pytest.raises(CsqlError, match="ruby") as err:
        csql_sim.validate(PROBLEM, ["(unstack coral ruby)"])
    assert "\n" not in str(err.value)


def test_validate_gives_the_verdict_of_the_validate_command(tmp_path, capsys):
    from csql_sim.cli import main

    plan = csql_sim.plan(PROBLEM)
    (tmp_path / "p.pddl").write_text(PROBLEM)
    (tmp_path / "bad.plan").write_text("\n".join([plan.lines[1], plan.lines[0], *plan.lines[2:]]))
    verdict = csql_sim.validate(tmp_path / "p.pddl", tmp_path / "bad.plan")
    assert main(["validate", "--problem", str(tmp_path / "p.pddl"), "--plan", str(tmp_path / "bad.plan")]) == 1
    printed = capsys.readouterr().out.splitlines()
    assert printed[: len(verdict.errors)] == list(verdict.errors) and not verdict.valid and verdict.applied == 0


@pytest.mark.parametrize("kwargs, names", [({"planner": "rules"}, "rules"), ({"planner": "astar"}, "planner"),
                                           ({"planner": "bfs", "rules": "x.json"}, "bfs")])
def test_a_planner_that_contradicts_the_rules_is_refused_in_one_line(kwargs, names):
    with pytest.raises(CsqlError, match=names) as err:
        csql_sim.plan(PROBLEM, **kwargs)
    assert "\n" not in str(err.value)


def test_a_problem_that_is_not_the_blocks_world_is_refused_naming_the_predicate():
    with pytest.raises(CsqlError, match="at-robby"):
        csql_sim.plan("(define (problem g) (:domain gripper) (:objects r1 r2) (:init (at-robby r1)) "
                      "(:goal (at-robby r2)))")


def test_rules_trained_by_the_api_plan_and_are_the_file_written(tmp_path):
    rules = csql_sim.train_lifted(tmp_path / "lifted.json", trials=200, sizes=(3,), seed=1)
    assert rules.path == tmp_path / "lifted.json" and rules.path.read_text() == rules.text
    assert rules.trials == 200 and rules.classifiers
    by_object, by_file = csql_sim.plan(PROBLEM, rules=rules), csql_sim.plan(PROBLEM, rules=rules.path)
    assert by_object.actions == by_file.actions and by_file.planner == "rules"
    if by_file.solved:
        assert csql_sim.validate(PROBLEM, by_file).valid


def test_execute_runs_the_builtin_plan_on_the_arm_and_judges_from_perception():
    run = csql_sim.execute(PROBLEM)
    assert run.reached and run.reason == "" and run.video is None
    plan = csql_sim.plan(PROBLEM)
    assert run.actions == plan.length
    assert run.final == "Amber jade coral pearl"  # the goal tower, bottom up, in the file's names


def test_execute_follows_the_builtin_rules_by_name():
    from csql_sim.infra.assets import builtin_rules_path

    two = ("(define (problem two) (:domain blocks) (:objects amber pearl) "
           "(:init (handempty) (on amber pearl) (ontable pearl) (clear amber)) (:goal (on pearl amber)))")
    run = csql_sim.execute(two, rules="builtin")
    assert run.reached and run.final == "amber pearl"
    assert run.report.source == {"kind": "rules", "file": str(builtin_rules_path())}


def _ring(n: int) -> str:
    cubes = " ".join(f"c{i}" for i in range(n))
    init = " ".join(f"(ontable c{i}) (clear c{i})" for i in range(n))
    return f"(define (problem ring{n}) (:domain blocks) (:objects {cubes}) (:init (handempty) {init}) " \
           f"(:goal (and (on c{n - 1} c{n - 2}))))"


def test_execute_takes_thirty_cubes_and_refuses_31_before_planning():
    """Past 26 objects the problem was refused (read as letters A-Z) although the arm takes 30 cubes."""
    run = csql_sim.execute(_ring(30))
    assert run.reached and run.actions == 2 and "c28 c29" in run.final  # in the problem's names, as perceived
    with pytest.raises(CsqlError, match="at most 30 cubes"):
        csql_sim.execute(_ring(31))
