"""``execute`` past six blocks: eight named cubes, an outside planner's plan file and a partial goal."""

from pathlib import Path

import pytest

from csql_sim.core.files.pddl_import import read_problem
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import State
from csql_sim.jobs.execute import execute_problem
from csql_sim.sim.control.physical import PhysicalWorld

DATA = Path(__file__).resolve().parents[1] / "data" / "problems"
PROBLEM, PLAN = DATA.parent / "large" / "blocks8-names.pddl", DATA.parent / "large" / "blocks8-names.plan"
DOMAIN = DATA / "domain.pddl"
LIFTED = Path(__file__).resolve().parents[2] / "assets" / "rules" / "lifted.json"


def _perceived_afresh(result) -> State:
    """The final poses of the run, set in a new scene and perceived there by the cameras."""
    with PhysicalWorld(result.blocks, seed=0, perception="camera") as world:
        for i, pose in enumerate(result.episode.final_poses):
            world.scene.set_block_pose(i, pose.position, pose.orientation)
        return world.perceive().state


@pytest.mark.slow
def test_a_plan_file_for_eight_named_cubes_reaches_a_partial_goal_as_perceived():
    problem = read_problem(PROBLEM, DOMAIN)
    assert problem.n == 8 and problem.goal.partial and not problem.goal.satisfied(problem.start)
    result = execute_problem(PROBLEM, DOMAIN, plan=PLAN, perception="camera")
    assert result.reached, result.explain()
    plan_lines = [line for line in PLAN.read_text().splitlines() if line and not line.startswith(";")]
    assert [s.text for s in result.steps] == plan_lines and all(s.status == "ok" for s in result.steps)
    assert problem.goal.satisfied(parse_config(result.final))
    seen = _perceived_afresh(result)
    assert problem.goal.satisfied(seen) and seen.notation() == result.final
    report = result.to_dict()
    assert report["objects"]["x-ray"] == "H" and report["goal"]["partial"] is True and report["goal"]["states"] is None
    assert report["legend"]["x-ray"] == "magenta" and report["legend"]["amber_1"] == "red"
    assert "legend: amber_1 = red, b2 = green, b10 = blue, ivory = yellow, jade = purple, ruby = orange, " \
           "slate = cyan, x-ray = magenta" in result.lines()


@pytest.mark.slow
@pytest.mark.parametrize("source", [{"rules": LIFTED}, {"planner": "gn1"}])
def test_lifted_rules_and_gn1_reach_the_same_partial_goal(source):
    problem = read_problem(PROBLEM, DOMAIN)
    result = execute_problem(PROBLEM, DOMAIN, **source)
    assert result.reached, result.explain()
    assert problem.goal.satisfied(_perceived_afresh(result))
    assert result.target == problem.goal.nearest(problem.start).notation()
