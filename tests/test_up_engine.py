"""``OneshotPlanner(name="csql-sim")``: UP's blocks-world problems, planned and validated by UP (issue 52).

Only UP's verdicts are asserted (statuses, validity), never its wording.
"""

import numpy as np
import pytest

up = pytest.importorskip("unified_planning")

from unified_planning.engines import PlanGenerationResultStatus, ValidationResultStatus  # noqa: E402
from unified_planning.io import PDDLReader  # noqa: E402
from unified_planning.shortcuts import (  # noqa: E402
    BoolType,
    Fluent,
    InstantaneousAction,
    Object,
    OneshotPlanner,
    PlanValidator,
    Problem,
    UserType,
    get_environment,
)

from csql_sim.core.measure.optimum import optimal_length  # noqa: E402
from csql_sim.core.state.state_count import sample_state  # noqa: E402
from csql_sim.core.state.world import HAND  # noqa: E402
from csql_sim.infra.assets import asset_text  # noqa: E402
from csql_sim.jobs.problems import relational_problem_text  # noqa: E402
from csql_sim.up_engine import ENGINE_NAME, CsqlSimPlanner, register  # noqa: E402

register()
SOLVED = (PlanGenerationResultStatus.SOLVED_SATISFICING, PlanGenerationResultStatus.SOLVED_OPTIMALLY)


def _solve(problem):
    with OneshotPlanner(name=ENGINE_NAME) as planner:
        return planner.solve(problem)


def _valid(problem, plan):
    with PlanValidator(problem_kind=problem.kind) as validator:
        return validator.validate(problem, plan).status == ValidationResultStatus.VALID


def _blocks_world(names, start_towers, goal_atoms):
    """A 4-operator blocks-world problem built with UP's Python API (no file)."""
    block = UserType("block")
    on = Fluent("on", BoolType(), x=block, y=block)
    ontable, clear, holding = (Fluent(n, BoolType(), x=block) for n in ("ontable", "clear", "holding"))
    handempty = Fluent("handempty", BoolType())
    pick = InstantaneousAction("pick-up", x=block)
    x = pick.parameter("x")
    for pre in (clear(x), ontable(x), handempty):
        pick.add_precondition(pre)
    for fluent, value in ((ontable(x), False), (clear(x), False), (handempty, False), (holding(x), True)):
        pick.add_effect(fluent, value)
    put = InstantaneousAction("put-down", x=block)
    x = put.parameter("x")
    put.add_precondition(holding(x))
    for fluent, value in ((holding(x), False), (clear(x), True), (handempty, True), (ontable(x), True)):
        put.add_effect(fluent, value)
    stack = InstantaneousAction("stack", x=block, y=block)
    x, y = stack.parameters
    stack.add_precondition(holding(x))
    stack.add_precondition(clear(y))
    for fluent, value in ((holding(x), False), (clear(y), False), (clear(x), True), (handempty, True),
                          (on(x, y), True)):
        stack.add_effect(fluent, value)
    unstack = InstantaneousAction("unstack", x=block, y=block)
    x, y = unstack.parameters
    for pre in (on(x, y), clear(x), handempty):
        unstack.add_precondition(pre)
    for fluent, value in ((holding(x), True), (clear(y), True), (clear(x), False), (handempty, False),
                          (on(x, y), False)):
        unstack.add_effect(fluent, value)
    problem = Problem("built")
    for fluent in (on, ontable, clear, handempty, holding):
        problem.add_fluent(fluent, default_initial_value=False)
    for action in (pick, put, stack, unstack):
        problem.add_action(action)
    objects = {name: Object(name, block) for name in names}
    problem.add_objects(objects.values())
    problem.set_initial_value(handempty, True)
    for tower in start_towers:
        problem.set_initial_value(ontable(objects[tower[0]]), True)
        problem.set_initial_value(clear(objects[tower[-1]]), True)
        for below, above in zip(tower, tower[1:], strict=False):
            problem.set_initial_value(on(objects[above], objects[below]), True)
    for above, below in goal_atoms:
        problem.add_goal(on(objects[above], objects[below]))
    return problem


def test_a_problem_built_with_ups_python_api_is_solved_and_valid():
    names = ["amber", "pearl", "coral", "slate", "ivory"]
    problem = _blocks_world(names, [["amber", "pearl", "coral"], ["slate", "ivory"]],
                            [("amber", "ivory"), ("ivory", "coral"), ("pearl", "slate")])
    result = _solve(problem)
    assert result.status in SOLVED and result.engine_name == ENGINE_NAME
    assert _valid(problem, result.plan)
    # the plan's objects are the problem's own objects, by identity
    assert {str(p) for a in result.plan.actions for p in a.actual_parameters} <= set(names)


def test_a_thirty_block_tower_built_in_python_is_planned_optimally():
    names = [f"b{i}" for i in range(1, 31)]
    problem = _blocks_world(names, [[n] for n in names], list(zip(names[1:], names[:-1], strict=True)))
    result = _solve(problem)
    assert result.status in SOLVED and _valid(problem, result.plan)
    assert len(result.plan.actions) == 2 * 29  # each of 29 blocks picked up and stacked once: the optimum


@pytest.mark.parametrize("domain", ["blocks-4op.pddl", "blocks-move.pddl"])
def test_drawn_problems_read_by_ups_pddl_reader_get_valid_near_optimal_plans(tmp_path, domain):
    rng = np.random.default_rng(52)
    (tmp_path / "domain.pddl").write_text(asset_text("domains", domain))
    lengths = []
    for k in range(3):
        n = 9 + 3 * k
        start, goal = (_hand_empty(n, rng) for _ in range(2))
        text = relational_problem_text(f"drawn{k}", start, goal) if domain == "blocks-4op.pddl" else \
            _move_problem_text(f"drawn{k}", start, goal)
        (tmp_path / "p.pddl").write_text(text)
        problem = PDDLReader().parse_problem(str(tmp_path / "domain.pddl"), str(tmp_path / "p.pddl"))
        result = _solve(problem)
        assert result.status in SOLVED and _valid(problem, result.plan), (k, result.log_messages)
        per_move = 2 if domain == "blocks-4op.pddl" else 1
        lengths.append((len(result.plan.actions) * 2 // per_move, optimal_length(start, goal)))
    assert all(length >= optimum for length, optimum in lengths)
    assert sum(length for length, _ in lengths) <= 1.2 * sum(optimum for _, optimum in lengths)


def _move_problem_text(name, start, goal):
    """A task in the one-operator move domain (``assets/domains/blocks-move.pddl``: the table is an object)."""
    names = [f"b{i + 1}" for i in range(start.n)]

    def on(state):
        return [f"(on {names[i]} {'table' if s < 0 else names[s]})" for i, s in enumerate(state.support)]

    clear = [f"(clear {names[i]})" for i in range(start.n) if start.is_clear(i)]
    init = [*(f"(block {b})" for b in names), *on(start), *clear, "(clear table)"]
    return (f"(define (problem {name}) (:domain blocks-move) (:objects {' '.join(names)})\n"
            f"  (:init {' '.join(init)})\n  (:goal (and {' '.join(on(goal))})))\n")


def _hand_empty(n, rng):
    while True:
        state = sample_state(n, rng)
        if HAND not in state.support:
            return state


def test_a_problem_of_another_domain_is_unsupported():
    """A robot that moves between rooms: classical STRIPS, not the blocks world."""
    room = UserType("room")
    at = Fluent("at", BoolType(), r=room)
    move = InstantaneousAction("move", a=room, b=room)
    a, b = move.parameters
    move.add_precondition(at(a))
    move.add_effect(at(a), False)
    move.add_effect(at(b), True)
    problem = Problem("robot")
    problem.add_fluent(at, default_initial_value=False)
    problem.add_action(move)
    kitchen, hall = Object("kitchen", room), Object("hall", room)
    problem.add_objects([kitchen, hall])
    problem.set_initial_value(at(kitchen), True)
    problem.add_goal(at(hall))
    assert CsqlSimPlanner.supports(problem.kind)  # UP's kind check lets it through: the engine itself refuses
    result = _solve(problem)
    assert result.status == PlanGenerationResultStatus.UNSUPPORTED_PROBLEM and result.plan is None


def test_a_domain_that_only_looks_like_the_blocks_world_is_unsupported():
    """``stack`` that forgets to clear the stacked block: the names match, the plan would not be valid."""
    names = ["a", "b", "c"]
    problem = _blocks_world(names, [["a", "b", "c"]], [("a", "c"), ("c", "b")])
    stack = problem.action("stack")
    stack.clear_effects()
    x, y = stack.parameters
    fluents = {f.name: f for f in problem.fluents}
    for fluent, value in ((fluents["holding"](x), False), (fluents["clear"](y), False),
                          (fluents["handempty"], True), (fluents["on"](x, y), True)):
        stack.add_effect(fluent, value)
    result = _solve(problem)
    assert result.status == PlanGenerationResultStatus.UNSUPPORTED_PROBLEM and result.plan is None


def test_register_is_idempotent_and_the_engine_is_not_optimal():
    register()
    assert get_environment().factory.engines.count(ENGINE_NAME) == 1
    from unified_planning.engines.mixins.oneshot_planner import OptimalityGuarantee

    assert not CsqlSimPlanner.satisfies(OptimalityGuarantee.SOLVED_OPTIMALLY)


def test_a_timeout_is_ignored_with_a_warning_and_the_plan_still_comes():
    problem = _blocks_world(["a", "b"], [["a", "b"]], [("a", "b")])
    with OneshotPlanner(name=ENGINE_NAME) as planner, pytest.warns(UserWarning, match=ENGINE_NAME):
        result = planner.solve(problem, timeout=30)
    assert result.status in SOLVED and _valid(problem, result.plan)
