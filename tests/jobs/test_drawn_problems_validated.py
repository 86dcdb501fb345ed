"""A 300-block drawn problem planned by the lifted rules and GN1, each plan validated by unified-planning."""

from pathlib import Path

import numpy as np
import pytest

from csql_sim.core.model.task_draws import draw_task
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.lifted_policy import load_lifted_policy
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.world import ActionKind
from csql_sim.jobs.problems import DOMAIN_TEXT, block_names, drawn_problems, relational_problem_text

up = pytest.importorskip("unified_planning", reason="unified-planning is in the test extra: pip install '.[test]'")

SHIPPED = Path(__file__).resolve().parents[2] / "assets" / "rules" / "lifted.json"
NAMES = {ActionKind.PICKUP: "pick-up", ActionKind.PUTDOWN: "put-down", ActionKind.STACK: "stack",
         ActionKind.UNSTACK: "unstack"}


def _validate(domain: Path, problem: Path, actions, names) -> str:
    from unified_planning.io import PDDLReader
    from unified_planning.plans import ActionInstance, SequentialPlan
    from unified_planning.shortcuts import PlanValidator, get_environment

    get_environment().credits_stream = None
    task = PDDLReader().parse_problem(str(domain), str(problem))
    steps = []
    for a in actions:
        blocks = [a.block] if a.target is None else [a.block, a.target]
        steps.append(ActionInstance(task.action(NAMES[a.kind]), [task.object(names[b]) for b in blocks]))
    with PlanValidator(name="sequential_plan_validator") as validator:
        return validator.validate(task, SequentialPlan(steps)).status.name


@pytest.mark.parametrize("planner", ["rules", "gn1"])
def test_a_300_block_tall_tower_plan_is_valid_for_unified_planning(tmp_path, planner):
    (name, domain_text), (problem_name, text) = drawn_problems("tall-towers", [300], 1, seed=11)
    assert domain_text == DOMAIN_TEXT
    domain, problem = tmp_path / name, tmp_path / problem_name
    domain.write_text(domain_text)
    problem.write_text(text)
    start, goal = draw_task("tall-towers", 300, np.random.default_rng(11))
    assert text.endswith(relational_problem_text("tall-towers-300-01", start, goal))
    policy = load_lifted_policy(SHIPPED) if planner == "rules" else Gn1Policy()
    run = rollout_relational(policy, start, goal)
    assert run.reached and len(run.actions) >= 2 * 250
    assert _validate(domain, problem, run.actions, block_names(300)) == "VALID"
    assert _validate(domain, problem, run.actions[:-1], block_names(300)) == "INVALID"
