"""Plan files of ``plan --problem`` validated by unified-planning (an independent validator), up to 300 blocks."""

from pathlib import Path

import pytest

from csql_sim.core.files.ipc_plan import write_ipc_plan_lines
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.lifted_policy import load_lifted_policy
from csql_sim.jobs.plan_problems import plan_folder, plan_problem
from csql_sim.jobs.problems import drawn_problems

up = pytest.importorskip("unified_planning", reason="unified-planning is in the test extra: pip install '.[test]'")

SHIPPED = Path(__file__).resolve().parents[2] / "assets" / "rules" / "lifted.json"
MOVE_DOMAIN = """(define (domain blocksworld)
  (:requirements :strips)
  (:predicates (clear ?x) (on-table ?x) (on ?x ?y))
  (:action move-b-to-b :parameters (?bm ?bf ?bt)
    :precondition (and (clear ?bm) (clear ?bt) (on ?bm ?bf))
    :effect (and (not (clear ?bt)) (not (on ?bm ?bf)) (on ?bm ?bt) (clear ?bf)))
  (:action move-b-to-t :parameters (?bm ?bf)
    :precondition (and (clear ?bm) (on ?bm ?bf))
    :effect (and (not (on ?bm ?bf)) (on-table ?bm) (clear ?bf)))
  (:action move-t-to-b :parameters (?bm ?bt)
    :precondition (and (clear ?bm) (clear ?bt) (on-table ?bm))
    :effect (and (not (clear ?bt)) (not (on-table ?bm)) (on ?bm ?bt))))
"""


def validated(domain: Path, problem: Path, plan: Path) -> str:
    """unified-planning's verdict (``VALID``/``INVALID``) on a plan file of a problem."""
    from unified_planning.io import PDDLReader
    from unified_planning.shortcuts import PlanValidator, get_environment

    get_environment().credits_stream = None
    reader = PDDLReader()
    task = reader.parse_problem(str(domain), str(problem))
    with PlanValidator(name="sequential_plan_validator") as validator:
        return validator.validate(task, reader.parse_plan(task, str(plan))).status.name


def written(tmp_path, lines, name="p.plan"):
    return write_ipc_plan_lines(lines, tmp_path / name, header="; test plan")


@pytest.mark.parametrize("planner", ["rules"])  # GN1 at 300 blocks: tests/jobs/test_drawn_problems_validated.py
def test_a_300_block_problem_file_is_planned_and_its_plan_file_valid(tmp_path, planner):
    (_, domain_text), (name, text) = drawn_problems("tall-towers", [300], 1, seed=17)
    domain, problem = tmp_path / "domain.pddl", tmp_path / name
    domain.write_text(domain_text)
    problem.write_text(text)
    policy = load_lifted_policy(SHIPPED) if planner == "rules" else Gn1Policy()
    plan = plan_problem(problem, domain, lambda n: policy, planner, budget_s=0.0)
    assert plan.solved and plan.blocks == 300 and len(plan.lines) >= plan.lower_bound >= 2 * 250
    assert validated(domain, problem, written(tmp_path, plan.lines)) == "VALID"
    assert validated(domain, problem, written(tmp_path, plan.lines[:-1], "short.plan")) == "INVALID"


def test_a_move_domain_plan_file_is_valid(tmp_path):
    blocks = [f"b{i}" for i in range(1, 13)]  # two towers b1..b6, b7..b12; the goal one tower b12..b1
    init = "(on-table b1) (on-table b7) " + " ".join(f"(on {blocks[i + 1]} {blocks[i]})" for i in (0, 1, 2, 3, 4))
    init += " " + " ".join(f"(on {blocks[i + 1]} {blocks[i]})" for i in (6, 7, 8, 9, 10)) + " (clear b6) (clear b12)"
    goal = " ".join(f"(on {blocks[i]} {blocks[i + 1]})" for i in range(11))
    domain, problem = tmp_path / "d.pddl", tmp_path / "p.pddl"
    domain.write_text(MOVE_DOMAIN)
    problem.write_text(f"(define (problem two) (:domain blocksworld) (:objects {' '.join(blocks)}) (:init {init}) "
                       f"(:goal (and {goal})))")
    plan = plan_problem(problem, domain, lambda n: Gn1Policy(), "gn1", budget_s=1.0)
    assert plan.solved and all(line.startswith("(move-") for line in plan.lines)
    assert len(plan.lines) * 2 == len(plan.actions) and plan.optimum.lower <= len(plan.actions)
    assert validated(domain, problem, written(tmp_path, plan.lines)) == "VALID"


def test_a_folder_plans_every_problem(tmp_path):
    for name, text in drawn_problems("uniform", [10, 30], 2, seed=5):
        (tmp_path / name).write_text(text)
    policy = load_lifted_policy(SHIPPED)
    plans = plan_folder(tmp_path, tmp_path / "domain.pddl", lambda n: policy, "rules", budget_s=0.0)
    assert [p.blocks for p in plans] == [10, 10, 30, 30] and all(p.solved for p in plans)
    for p in plans:
        assert validated(tmp_path / "domain.pddl", Path(p.problem), written(tmp_path, p.lines)) == "VALID"
