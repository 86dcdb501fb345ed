"""The video's framing: every tower of the start and the goal in the picture, no tower behind another."""

import math

import numpy as np

from csql_sim.sim.video.framing import goal_camera, top_camera, towers
from csql_sim.sim.video.painter import Projection
from csql_sim.sim.world.config import WIDE_CONFIG
from csql_sim.sim.world.scene import Pose

CUBE = WIDE_CONFIG.physics.cube_size
UPRIGHT = (0.0, 0.0, 0.0, 1.0)


def _tower(x, y, k):
    return [Pose((x, y, CUBE / 2 + CUBE * i), UPRIGHT) for i in range(k)]


def _on_arc(degrees, k):
    a = math.radians(degrees)
    return _tower(0.64 * math.cos(a), 0.64 * math.sin(a), k)


def _columns(camera, poses, width, height):
    """Each tower's horizontal pixel span (its cubes' centres, widened by half a cube each side)."""
    proj = Projection.of(camera, width, height)
    spans = []
    for col in towers(poses, CUBE):
        xy, depth = proj(col)
        half = proj.focal * CUBE / 2 / depth.min()
        spans.append((xy[:, 0].min() - half, xy[:, 0].max() + half))
    return sorted(spans)


def test_three_towers_in_a_row_are_seen_side_by_side_and_whole():
    # the goal: three towers of 4, 3 and 3 on the arc at -40, 0 and 40 degrees; the start: ten on the table
    last = _on_arc(-40, 4) + _on_arc(0, 3) + _on_arc(40, 3)
    first = [p for i in range(10) for p in _on_arc(-64 + i * 128 / 9, 1)]
    camera = goal_camera(first, last, WIDE_CONFIG, 640, 480)
    proj = Projection.of(camera, 640, 480)
    for poses in (first, last):
        xy, depth = proj(np.asarray([p.position for p in poses]))
        assert (depth > camera.near).all()
        assert (xy[:, 0] > 10).all() and (xy[:, 0] < 630).all() and (xy[:, 1] > 10).all() and (xy[:, 1] < 430).all()
        spans = _columns(camera, poses, 640, 480)
        assert all(b[0] > a[1] for a, b in zip(spans, spans[1:], strict=False)), "no tower hides another"


def test_towers_one_behind_another_from_the_front_are_seen_from_an_angle():
    # two towers on the x axis, one behind the other as seen from straight in front
    last = _tower(0.45, 0.0, 3) + _tower(0.65, 0.0, 3)
    camera = goal_camera(last, last, WIDE_CONFIG, 640, 480)
    spans = _columns(camera, last, 640, 480)
    assert spans[1][0] > spans[0][1]


def test_the_top_view_looks_down_with_the_arm_s_base_at_the_top():
    poses = _on_arc(-40, 1) + _on_arc(40, 1)
    camera = top_camera(poses, poses, 213, 160)
    proj = Projection.of(camera, 213, 160)
    xy, _ = proj(np.asarray([[0.0, 0.0, 0.0], [0.64, 0.0, 0.0], *[p.position for p in poses]]))
    base, front, left, right = xy
    assert base[1] < front[1], "the base (x = 0) is above the front of the table"
    assert right[0] > left[0], "+y is to the right, as in the main view"
    inside = xy[[0, 2, 3]]  # the base and the cubes
    assert ((inside >= 0) & (inside <= [213, 160])).all()
