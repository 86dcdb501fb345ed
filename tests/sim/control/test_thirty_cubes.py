"""Past ten cubes on the arm: a tall-tower task of 20 cubes, its names past Z, and the arm fixture."""

import numpy as np
import pytest

from csql_sim.core.model.task_draws import draw_task
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state import default_names
from csql_sim.sim.world import MAX_TOWER_HEIGHT
from csql_sim.sim.world.arm_state import Messages
from csql_sim.testing.plugin import assert_reached


def test_names_past_z_and_no_message_past_26_cubes():
    names = default_names(30)
    assert names[25:28] == ("Z", "AA", "AB")
    state = parse_config(" ".join(names))
    assert state.notation() == " ".join(names) and parse_config(state.notation(), 30) == state
    assert Messages(state).state(state) == ""  # past 26 the policy reads the state, not a message


@pytest.mark.slow
def test_a_twenty_cube_tall_tower_task_reaches_its_goal_with_camera_perception(arm):
    start, goal = draw_task("tall-towers", 20, np.random.default_rng(2), max_height=MAX_TOWER_HEIGHT)
    result = arm.execute(planner="gn1", start=start.notation(), goal=goal.notation(), perception="camera")
    assert_reached(result)
    assert parse_config(result.final, 20) == goal
