"""Plans in a problem's words: each domain's action names and arity, read back by the plan reader."""

import pytest

from csql_sim.core.files.ipc_plan import PlanError, check_plan, parse_plan
from csql_sim.core.files.pddl_import import parse_problem_text
from csql_sim.core.files.plan_spelling import spelled_plan_lines, spelling_of
from csql_sim.core.state.world import Action, ActionKind

PROBLEM = ("(define (problem t) (:domain d) (:objects Red Blue) (:init (on Red Blue) (ontable Blue) (clear Red) "
           "(handempty)) (:goal (and (on Blue Red))))")
MOVE_PROBLEM = PROBLEM.replace("(ontable Blue)", "(on-table Blue)").replace(" (handempty)", "")
PLAN = (Action(ActionKind.UNSTACK, 1, 0), Action(ActionKind.PUTDOWN, 1), Action(ActionKind.PICKUP, 0),
        Action(ActionKind.STACK, 0, 1))  # Blue = block 0, Red = block 1 (sorted by name)


def domain(*actions):
    body = ":precondition (on ?a0 ?a0) :effect (not (on ?a0 ?a0))"
    parts = " ".join(f"(:action {name} :parameters ({' '.join(f'?a{i}' for i in range(k))}) {body})"
                     for name, k in actions)
    preds = "(on ?x ?y) (ontable ?x) (on-table ?x) (clear ?x) (handempty)"  # what the problems use
    return f"(define (domain d) (:requirements :strips) (:predicates {preds}) {parts})"


@pytest.mark.parametrize("problem, dom, expected", [
    (PROBLEM, None, ["(unstack Red Blue)", "(put-down Red)", "(pick-up Blue)", "(stack Blue Red)"]),
    (PROBLEM, domain(("pickup", 1), ("putdown", 1), ("stack", 2), ("unstack", 2)),
     ["(unstack Red Blue)", "(putdown Red)", "(pickup Blue)", "(stack Blue Red)"]),
    (MOVE_PROBLEM, None, ["(move-b-to-t Red Blue)", "(move-t-to-b Blue Red)"]),
    (MOVE_PROBLEM, domain(("move-b-to-b", 3), ("move-to-t", 2), ("move-t-to-b", 2)),
     ["(move-to-t Red Blue)", "(move-t-to-b Blue Red)"]),
    (MOVE_PROBLEM, domain(("move", 3)), ["(move Red Blue table)", "(move Blue table Red)"]),
    (MOVE_PROBLEM, domain(("move", 3), ("move-to-table", 2)), ["(move-to-table Red Blue)", "(move Blue table Red)"]),
])
def test_each_domain_gets_its_own_words_and_they_read_back(problem, dom, expected):
    bp = parse_problem_text(problem, domain_text=dom)
    lines = spelled_plan_lines(PLAN, spelling_of(bp))
    assert lines == expected
    end = check_plan(bp.start, parse_plan(lines, bp.index, bp.n, allowed=bp.actions))[-1]
    assert bp.goal.satisfied(end)


def test_a_move_domain_refuses_a_plan_it_cannot_say():
    bp = parse_problem_text(MOVE_PROBLEM)
    with pytest.raises(PlanError, match="picks each followed by a put"):
        spelled_plan_lines(PLAN[:3], spelling_of(bp))
    with pytest.raises(PlanError, match="from the table to the table"):
        spelled_plan_lines((Action(ActionKind.PICKUP, 0), Action(ActionKind.PUTDOWN, 0)), spelling_of(bp))
