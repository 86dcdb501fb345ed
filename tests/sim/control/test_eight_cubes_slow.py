"""A physical episode with eight cubes: a lifted policy on relational states, success from perception."""

import numpy as np
import pytest

from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.core.state.world import State, action_name, legal_actions, successor
from csql_sim.sim.control.executor import run_physical_episode
from csql_sim.sim.control.physical import PhysicalWorld


def _replay(start: State, names: list[str]) -> State:
    """The state the named actions lead to from ``start`` (STRIPS successor)."""
    state = start
    for name in names:
        state = next(successor(state, a) for a in legal_actions(state) if action_name(a) == name)
    return state


@pytest.mark.slow
@pytest.mark.parametrize("perception", ["pose", "camera"])
def test_an_eight_cube_episode_reaches_the_goal_as_perceived(perception):
    (start, goal), = sample_pairs(8, 1, np.random.default_rng(29))
    assert goal.held is None  # the final poses below are the goal's, with nothing in the hand
    result = run_physical_episode(start, goal, Gn1Policy(), seed=29, perception=perception)
    assert result.success, result.reason
    assert result.optimal_length == optimal_length(start, goal) > 0
    assert result.length >= result.optimal_length
    assert result.steps[-1].perceived == goal.notation()  # perceived after the last primitive
    assert all(len(s.message) == 3 * 8 + 3 + 2 for s in result.steps)  # the large message form
    if not any(s.recovery or s.mismatch for s in result.steps):  # a clean run replays symbolically to the goal
        assert _replay(start, [s.action for s in result.steps]) == goal
    with PhysicalWorld(8, seed=0) as world:  # the cubes really stand so: perceive their final poses afresh
        for i, pose in enumerate(result.final_poses):
            world.scene.set_block_pose(i, pose.position, pose.orientation)
        seen = world.perceive().state
    assert isinstance(seen, State) and seen == goal
