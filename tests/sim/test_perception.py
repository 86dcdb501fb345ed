import pytest

from csql_sim.message import format_state_message
from csql_sim.notation import parse_config
from csql_sim.sim.camera import CAMERA_TOLERANCES
from csql_sim.sim.perception import interpret, observe_poses, state_message
from csql_sim.sim.physical import PhysicalWorld
from csql_sim.sim.rgbd import observe_rgbd as observe_camera
from csql_sim.world import BlocksWorld, all_states


@pytest.mark.parametrize("state", all_states(3), ids=lambda s: s.notation())
def test_pose_and_camera_perception_agree_on_every_state(state):
    with PhysicalWorld(3, seed=3) as world:
        world.build(state)  # a held block gets there by a real grasp
        world.settle()
        by_pose = interpret(observe_poses(world.scene, world.panda))
        by_camera = interpret(observe_camera(world.scene, world.panda), CAMERA_TOLERANCES)
        assert by_pose.state == state, by_pose.reason
        assert by_camera.state == state, by_camera.reason


def test_state_message_of_perceived_state(task):
    start, goal = task
    with PhysicalWorld(3) as world:
        world.build(start)
        seen = world.perceive().state
        assert state_message(seen, goal) == "S0100000bct0000C"
        assert state_message(seen, goal) == format_state_message(start, BlocksWorld.of(3).state_index(goal))


def test_fallen_block_is_reported():
    with PhysicalWorld(3) as world:
        world.build(parse_config("A,B,C"))
        world.scene.set_block_pose(0, (1.2, 0, 0.02), (0, 0, 0, 1))
        world.scene.step(240)
        perceived = world.perceive()
        assert perceived.state is None and "fell off the table" in perceived.reason
