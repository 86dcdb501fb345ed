"""Ten cubes on the arm: markers the camera reads, the arc layout, reach, perception, refusals."""

import itertools
import math

import numpy as np
import pytest

from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.relational_message import format_large_message, parse_large_message
from csql_sim.core.state.state import default_names
from csql_sim.core.state.world import HAND, State
from csql_sim.sim.control.executor import run_physical_episode
from csql_sim.sim.control.physical import PhysicalWorld
from csql_sim.sim.control.primitives import OFFSETS
from csql_sim.sim.perception.camera import CAMERA_TOLERANCES, capture, perception_cameras
from csql_sim.sim.perception.fiducials import read_markers
from csql_sim.sim.perception.poses import interpret, observe_poses, state_message
from csql_sim.sim.perception.rgbd import observe_rgbd
from csql_sim.sim.world.arm_state import SimError, parse_arm_state, to_arm_state
from csql_sim.sim.world.config import DEFAULT_CONFIG, MAX_ARM_BLOCKS, WIDE_CONFIG, config_for
from csql_sim.sim.world.layout import arc_place, putdown_spots, start_layout
from csql_sim.sim.world.robot import EE_LINK, KINEMATIC_BODY, LOWER, UPPER
from csql_sim.sim.world.scene import Scene

TEN = ["JIHGFEDCBA", "A,B,C,D,E,F,G,H,I,J", "DCBA,E,GF,JIH", "AB,CD,EFG,HI+J"]


def test_every_view_reads_the_markers_of_ten_cubes_as_the_renderer_draws_them():
    with PhysicalWorld(10, seed=1) as world:
        world.build(parse_config("A,B,C,D,E,F,G,H,I,J"))
        seen = np.zeros(10, dtype=int)
        bodies = [world.scene.block_body(i) for i in range(10)]
        for cam in perception_cameras(10):
            rgb, _, ids = capture(world.scene, cam, cam.width, cam.height, segmentation=True)
            reads = read_markers(rgb, 10)
            for read in reads:  # the body under every read's centre is the cube of its id
                col, row = np.rint(read.centre).astype(int)
                assert ids[row, col] == bodies[read.cube], (cam, read.cube)
            seen[sorted({r.cube for r in reads})] += 1
        assert (seen >= 2).all(), seen  # every cube in at least two views


@pytest.mark.parametrize("notation", TEN)
def test_a_ten_cube_start_scene_is_perceived_exactly_by_pose_and_by_camera(notation):
    state = parse_config(notation)
    with PhysicalWorld(state.n, seed=3) as world:
        world.build(state)
        world.settle()
        by_pose = interpret(observe_poses(world.scene, world.panda))
        seen = observe_rgbd(world.scene, world.panda, rng=np.random.default_rng(5))
        by_camera = interpret(seen, CAMERA_TOLERANCES)
        assert isinstance(by_pose.state, State) and by_pose.state == state, by_pose.reason
        assert by_camera.state == state, by_camera.reason
        for x, b in enumerate(seen.blocks):
            if state.support[x] != HAND:  # seen flat, where it is
                assert b.tilt is not None and b.tilt < math.radians(3), (x, b.tilt)
                assert np.linalg.norm(np.subtract(b.position, world.scene.block_pose(x).position)) < 0.006
    goal = parse_config("ABCDEFGHIJ")
    message = state_message(by_camera.state, goal)  # the large message form past six blocks
    assert message == format_large_message(state, goal)
    assert parse_large_message(message).state == state


def test_the_arc_layout_holds_ten_towers_and_leaves_a_spot_for_every_putdown():
    lay = WIDE_CONFIG.layout
    places = [arc_place(WIDE_CONFIG, i) for i in range(lay.arc_positions)]
    for (x0, y0, _), (x1, y1, _) in itertools.pairwise(places):
        assert math.hypot(x1 - x0, y1 - y0) > lay.free_clearance  # a cube on one place leaves the next one free
    assert all(abs(math.hypot(x, y) - lay.arc_radius) < 1e-12 for x, y, _ in places)
    table_x, table_y = WIDE_CONFIG.physics.table_centre[:2]
    half = WIDE_CONFIG.physics.table_half_extents
    assert all(abs(x - table_x) < half[0] - 0.1 and abs(y - table_y) < half[1] - 0.1 for x, y, _ in places)
    placed = start_layout(parse_config("A,B,C,D,E,F,G,H,I,J"), WIDE_CONFIG)
    assert len({(round(p.x, 6), round(p.y, 6)) for p in placed}) == 10  # ten towers side by side
    assert lay.arc_positions >= 10  # nine cubes on the table (one held) leave a place free
    assert putdown_spots(WIDE_CONFIG) == [(x, y) for x, y, _ in places]
    assert config_for(6) is DEFAULT_CONFIG and config_for(7) is WIDE_CONFIG  # six cubes: as before


def test_the_arm_reaches_every_place_from_the_table_to_above_a_tower_of_ten():
    size = WIDE_CONFIG.physics.cube_size
    top_grasp = size / 2 + 9 * size  # the top cube of a tower of ten
    carry = 10 * size + size / 2 + OFFSETS.carry_clearance  # the grasp point of every move above such a tower
    with PhysicalWorld(10, seed=0) as world:
        model = world.scene.kinematics
        assert model is not None
        for i in range(WIDE_CONFIG.layout.arc_positions):
            x, y, yaw = arc_place(WIDE_CONFIG, i)
            for z in (size / 2, top_grasp, carry):
                for turn in (0.0, math.pi / 2):
                    hand = world.panda.wrist_fit(x, y)(yaw + turn)
                    q = world.panda.ik((x, y, z), hand)
                    assert all(lo - 1e-6 <= v <= hi + 1e-6 for v, lo, hi in zip(q, LOWER, UPPER, strict=True))
                    for j, v in enumerate(q):
                        model.reset_joint(KINEMATIC_BODY, j, v)
                    reached = model.link_state(KINEMATIC_BODY, EE_LINK)[0]
                    assert np.linalg.norm(np.subtract(reached, (x, y, z))) < 0.003, (i, z, turn)


def test_more_than_thirty_cubes_are_refused_with_the_reason():
    assert MAX_ARM_BLOCKS == 30
    with pytest.raises(SimError, match="at most 30 cubes .*ring.*reach"):
        Scene(31)
    start = parse_config(", ".join(default_names(31)))
    goal = parse_config(" ".join(default_names(31)))
    with pytest.raises(SimError, match="at most 30 cubes"):
        run_physical_episode(start, goal, Gn1Policy())


def test_camera_perception_takes_thirty_cubes_and_reads_every_marker_of_the_built_scene():
    with PhysicalWorld(30, perception="camera", seed=0) as world:
        start = parse_config(", ".join(default_names(30)))
        world.build(start)
        seen = world.perceive()
        assert seen.state == start and not seen.unseen, seen.reason


def test_bfs_and_ground_policies_are_refused_past_six_blocks_before_any_physics():
    start, goal = parse_config("A,B,C,D,E,F,G"), parse_config("GFEDCBA")
    with pytest.raises(SimError, match="BFS"):
        run_physical_episode(start, goal)

    class Ground:
        name, blocks = "rules", 3

        def act(self, state, goal):  # pragma: no cover - never asked
            raise AssertionError("a ground policy was asked past six blocks")

    with pytest.raises(SimError, match="ground rule base is for 3 blocks"):
        run_physical_episode(start, goal, Ground())


def test_states_take_the_arms_kind_for_their_size():
    assert isinstance(parse_arm_state("CBA"), State) and isinstance(parse_arm_state("GFEDCBA"), State)
    assert isinstance(to_arm_state(parse_config("CBA")), State)
    assert to_arm_state(parse_config("CBA")) == parse_config("CBA")


def test_a_seven_cube_episode_is_captioned_with_letters_past_f(tmp_path):
    from csql_sim.sim.video.writing import ReplayRenderer, video_view

    start, goal = parse_config("A,B,C,D,E,F,G"), parse_config("A,B,C,D,E,GF")
    result = run_physical_episode(start, goal, Gn1Policy(), seed=0, record=True, fps=10)
    assert result.success and [s.action for s in result.steps] == ["pickup(F)", "stack(F,G)"]
    assert result.optimal_length == 2 and result.steps[0].message == format_large_message(start, goal)
    captions = {f.caption.text(result.length) for f in result.recording.frames}
    # the message the policy saw before stacking, the one the step table prints
    assert result.steps[1].message == format_large_message(parse_config("A,B,C,D,E,G+F"), goal)
    assert f"step 2/2  stack(F,G)  {result.steps[1].message}" in captions
    assert any(c.startswith("step 2/2  goal A,B,C,D,E,GF  reached") for c in captions)
    renderer = ReplayRenderer("tiny")
    try:
        frames = renderer.render(7, result.recording.config, result.recording.frames[-1:],
                                 video_view(result.recording, 160, 120))
    finally:
        renderer.close()
    assert frames[0].shape == (120, 160, 3)
