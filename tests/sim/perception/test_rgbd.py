"""Camera perception by markers: the right cube, or an unseen one; never a guess."""

import dataclasses

import numpy as np
import pytest

from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state_count import sample_state
from csql_sim.sim.control.physical import PhysicalWorld
from csql_sim.sim.perception import rgbd
from csql_sim.sim.perception.camera import CAMERA_TOLERANCES, capture, fallback_cameras, perception_cameras
from csql_sim.sim.perception.face_reads import FaceRead
from csql_sim.sim.perception.fiducials import READ_LIMITS, RETRY_LIMITS
from csql_sim.sim.perception.poses import Observation, interpret
from csql_sim.sim.perception.rgbd import CameraNoise, locate_cubes, observe_rgbd
from csql_sim.sim.world.config import COLOURS
from csql_sim.sim.world.markers import erase_markers, marker_texture

NOISE = CameraNoise(depth=0.0015, colour=4.0)
"""The documented sensor noise (``--camera-noise 1.5,4``)."""


def _seen(world, noise=NOISE, fallback=None):
    return interpret(observe_rgbd(world.scene, world.panda, noise=noise, rng=np.random.default_rng(5),
                                  fallback=fallback), CAMERA_TOLERANCES)


def _wall_in(scene, i, gap=0.03, height=0.14, half=0.003):
    """Four static walls round cube i, ``gap`` from its faces: above the usual views' line of sight, open on top."""
    x, y, _ = scene.block_pose(i).position
    d = 0.02 + gap + half
    for dx, dy, hx, hy in ((d, 0, half, d + half), (-d, 0, half, d + half), (0, d, d + half, half),
                           (0, -d, d + half, half)):
        scene.add_box((hx, hy, height / 2), 0.0, (0.5, 0.5, 0.5, 1.0), (x + dx, y + dy, height / 2))


def test_a_cube_hidden_from_the_usual_views_is_read_from_a_further_one():
    with PhysicalWorld(3, seed=2) as world:
        world.build(parse_config("A,B,C"))
        _wall_in(world.scene, 1)
        assert _seen(world, fallback=()).unseen == (1,)  # the three usual views do not read B
        rendered = []

        def render(camera):
            rendered.append(camera)
            return capture(world.scene, camera, camera.width, camera.height)[:2]

        blocks = locate_cubes(render, perception_cameras(3), 3, 0.04, NOISE, np.random.default_rng(5),
                              fallback_cameras(3))
        observation = Observation(blocks, tuple(world.panda.ee_position()), world.panda.finger_width(), 0.04)
        assert interpret(observation, CAMERA_TOLERANCES).state == parse_config("A,B,C")
        assert rendered[:3] == list(perception_cameras(3)) and 3 < len(rendered) <= 3 + len(fallback_cameras(3))


def test_a_cube_with_its_markers_erased_is_unseen_not_guessed():
    with PhysicalWorld(4, seed=2, perception="camera") as world:
        world.build(parse_config("AB,C,D"))
        assert world.perceive().state == parse_config("AB,C,D")
        erase_markers(world.scene, [world.scene.block_body(2)], [COLOURS[2]])  # C keeps its paint, loses its marker
        perceived = world.perceive()
        assert perceived.state is None and perceived.unseen == (2,)
        assert "unseen cube C" in perceived.reason


def test_a_cube_covered_by_another_body_is_unseen_not_guessed():
    with PhysicalWorld(3, seed=2) as world:
        world.build(parse_config("A,B,C"))
        x, y, z = world.scene.block_pose(1).position
        world.scene.add_box((0.035, 0.035, 0.035), 0.0, (0.5, 0.5, 0.5, 1.0), (x, y, z))  # a box over B
        perceived = _seen(world)
        assert perceived.state is None and perceived.unseen == (1,)


def test_one_marker_in_two_places_is_no_cube_at_all():
    with PhysicalWorld(3, seed=2) as world:
        world.build(parse_config("A,B,C"))
        scene = world.scene
        scene.set_texture(scene.block_body(1), scene.load_texture(str(marker_texture(0, COLOURS[1]))))  # B wears A's
        perceived = _seen(world)
        assert perceived.state is None and perceived.unseen == (0, 1)


def test_a_held_cube_is_seen_in_the_hand_or_placed_there_by_elimination():
    state = parse_config("AB,C+D")
    with PhysicalWorld(4, seed=1) as world:
        world.build(state)
        assert _seen(world).state == state


def _ten(seed):
    state = sample_state(10, np.random.default_rng(seed))
    with PhysicalWorld(10, seed=seed) as world:
        world.build(state)
        world.settle()
        perceived = _seen(world)
    assert perceived.state == state, (state.notation(), perceived.reason)


def test_ten_cubes_with_sensor_noise_are_perceived_as_built():
    _ten(0)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(1, 9))
def test_seeded_ten_cube_scenes_with_sensor_noise_are_perceived_as_built(seed):
    _ten(seed)


def test_further_views_are_rendered_only_while_a_cube_is_unread_and_unexplained():
    small = tuple(dataclasses.replace(c, width=64, height=48) for c in perception_cameras(3) + fallback_cameras(3))
    usual, further = small[:3], small[3:]
    rendered = []

    def blank(camera):  # a view with no marker in it: nothing is read
        rendered.append(camera)
        return np.zeros((camera.height, camera.width, 3), np.uint8), np.ones((camera.height, camera.width))

    blocks = locate_cubes(blank, usual, 3, 0.04, fallback=further)
    assert rendered == list(small) and not any(b.visible for b in blocks)  # every view, and still no guess
    rendered.clear()
    locate_cubes(blank, usual, 3, 0.04, fallback=further, explained=lambda blocks: True)
    assert rendered == list(usual)  # nothing left to explain: no further view


# a green cube (B) under another on the ring, as an episode left them: its marker, in plain view of
# the front camera, decoded at 4, 6 and 10 pixels a cell and not at 8
# (OpenCV 5.1; were a release to read it at 8, the test would still hold)
B_POSE = ((0.44984, -0.21839, 0.01999), (0.0, 0.0, -0.84398, 0.53638))
G_ON_B = ((0.44925, -0.21782, 0.05998), (0.0, 0.0, -0.21276, 0.97710))


def test_a_marker_the_first_decoding_misses_is_read_by_the_second():
    with PhysicalWorld(12, seed=0) as world:
        world.build(parse_config("A,B,C,D,E,F,G,H,I,J,K,L"))
        scene = world.scene
        for i in (0, 2, 3, 4, 5, 7, 8, 9, 10, 11):  # the others out of sight
            pose = scene.block_pose(i)
            scene.set_block_pose(i, (pose.position[0], pose.position[1] + 3.0, pose.position[2]), pose.orientation)
        scene.set_block_pose(1, *B_POSE)
        scene.set_block_pose(6, *G_ON_B)
        front = perception_cameras(12)[0]
        blocks = locate_cubes(lambda camera: capture(scene, camera, camera.width, camera.height)[:2], (front,), 12,
                              0.04)
    assert blocks[1].visible and blocks[6].visible  # B read from the front view alone
    assert np.linalg.norm(np.subtract(blocks[1].position, B_POSE[0])) < 0.01
    assert np.linalg.norm(np.subtract(blocks[6].position, G_ON_B[0])) < 0.01
    assert not any(b.visible for i, b in enumerate(blocks) if i not in (1, 6))


def test_the_second_decoding_only_adds_reads_of_cubes_the_first_did_not_read(monkeypatch):
    calls = []

    def read_view(camera, rgb, depth, n, size, noise=0.0, limits=READ_LIMITS):
        calls.append(limits)
        cubes = (0, 1) if limits is RETRY_LIMITS else (0,)  # the second decoding reads cube 1 too
        return [FaceRead(c, np.full((12, 3), 0.1 * c) + np.eye(3)[np.arange(12) % 3] * 1e-3, np.array([1.0, 0, 0]),
                         0.0, np.array([0, 1.0, 0])) for c in cubes]

    monkeypatch.setattr(rgbd, "read_view", read_view)
    cameras = perception_cameras(3)[:2]
    blocks = locate_cubes(lambda camera: (None, None), cameras, 3, 0.04)
    assert calls == [READ_LIMITS] * 2 + [RETRY_LIMITS] * 2  # cube 2 is never read: one more pass, no more
    assert [b.reads for b in blocks] == [2, 2, 0]  # cube 0 read once a view, not twice; cube 1 by the second pass
