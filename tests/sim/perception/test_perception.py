import math

import numpy as np
import pytest

from csql_sim.core.state.message import format_state_message
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import HAND, BlocksWorld, all_states
from csql_sim.sim.control.physical import PhysicalWorld
from csql_sim.sim.perception.camera import CAMERA_TOLERANCES, PERCEPTION_CAMERA, capture
from csql_sim.sim.perception.fiducials import read_markers
from csql_sim.sim.perception.poses import interpret, observe_poses, state_message
from csql_sim.sim.perception.rgbd import NO_NOISE, CameraNoise, observe_rgbd


def _agree(state, noise=NO_NOISE):
    with PhysicalWorld(state.n, seed=3) as world:
        world.build(state)  # a held block gets there by a real grasp
        world.settle()
        by_pose = interpret(observe_poses(world.scene, world.panda))
        seen = observe_rgbd(world.scene, world.panda, noise=noise, rng=np.random.default_rng(5))
        by_camera = interpret(seen, CAMERA_TOLERANCES)
        assert by_pose.state == state, by_pose.reason
        assert by_camera.state == state, by_camera.reason
        for x, b in enumerate(seen.blocks):  # flat cubes are seen flat, where they are
            if state.support[x] != HAND:
                assert b.tilt is not None and b.tilt < math.radians(3), (x, b.tilt)
                assert np.linalg.norm(np.subtract(b.position, world.scene.block_pose(x).position)) < 0.006


@pytest.mark.parametrize("state", all_states(3), ids=lambda s: s.notation())
def test_pose_and_camera_perception_agree_on_every_state(state):
    _agree(state)


@pytest.mark.slow
@pytest.mark.parametrize("state", all_states(4), ids=lambda s: s.notation())
def test_pose_and_camera_perception_agree_on_every_state_of_four(state):
    _agree(state)


@pytest.mark.parametrize("notation", ["A,B,C", "CBA", "AB+C"])
def test_camera_perception_with_sensor_noise(notation):
    _agree(parse_config(notation), CameraNoise(depth=0.0015, colour=4.0))


def test_marker_reads_are_the_cubes_the_renderer_draws_there():
    with PhysicalWorld(4, seed=1) as world:
        world.build(parse_config("AB,C+D"))
        cam = PERCEPTION_CAMERA
        rgb, _, ids = capture(world.scene, cam, cam.width, cam.height, segmentation=True)
        reads = read_markers(rgb, 4)
        for read in reads:
            col, row = np.rint(read.centre).astype(int)
            assert ids[row, col] == world.scene.block_body(read.cube), read.cube
        assert {r.cube for r in reads} >= {0, 1, 2}  # the held cube D may be hidden by the hand


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
