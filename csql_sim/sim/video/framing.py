"""Framing a video: a view that shows every tower of the start and the goal, and a top view.

:func:`goal_camera` looks at the cubes of a recording's first and last frames from the
front of the table, from the azimuth (of a few, front first) that leaves the widest gap
between the towers' columns on the screen, so no tower stands behind another; the
distance is set so that every cube is in the picture. :func:`top_camera` looks down on
the whole table (the second view of the videos). Both depend only on the recording and
the frame size, never on who renders.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from csql_sim.sim.perception.camera import Camera
from csql_sim.sim.world.config import SimConfig
from csql_sim.sim.world.scene import Pose

AZIMUTHS = (0.0, 12.0, -12.0, 24.0, -24.0, 36.0, -36.0)  # degrees about z from the +x axis, front first
ELEVATION = 38.0  # degrees above the table
FOV = 40.0  # vertical field of view, degrees
BOX = ((-0.86, -0.74), (0.86, 0.25))  # where the cubes go in the picture (normalised: -1..1, y up), below
# the top view's inset and above the caption, leaving room for the arm above
HALF_WIDTH = 0.6  # a tower's half-width on the screen, in cubes (a cube turned by 45 degrees: 0.71)
MIN_GAP = 0.01  # a clear gap between towers on the screen: 0.5 % of the picture's width
TOP_HEIGHT = 2.0  # m above the table, the top view's eye
TOP_MARGIN = 0.08  # m around the cubes in the top view


def towers(poses: Sequence[Pose], cube: float) -> list[np.ndarray]:
    """The cubes' centres grouped into columns (cubes whose xy are within half a cube), in a fixed order."""
    centres = np.asarray([p.position for p in poses], dtype=float)
    groups: list[list[int]] = []
    for i in np.lexsort((centres[:, 1], centres[:, 0])):
        for g in groups:
            if np.linalg.norm(centres[g[0], :2] - centres[i, :2]) < cube / 2:
                g.append(int(i))
                break
        else:
            groups.append([int(i)])
    return [centres[g] for g in groups]


def _camera(target: np.ndarray, azimuth: float, distance: float, aspect: float) -> Camera:
    az, el = math.radians(azimuth), math.radians(ELEVATION)
    d = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
    eye = target + distance * d
    return Camera(eye=tuple(float(v) for v in eye), target=tuple(float(v) for v in target), fov=FOV)


def _ndc(camera: Camera, points: np.ndarray, aspect: float) -> np.ndarray:
    view, proj = camera.matrices(int(round(480 * aspect)), 480)
    m = np.asarray(proj).reshape(4, 4, order="F") @ np.asarray(view).reshape(4, 4, order="F")
    clip = points @ m[:, :3].T + m[:, 3]
    return clip[:, :2] / clip[:, 3:4]


def _fitted(target: np.ndarray, azimuth: float, points: np.ndarray, aspect: float) -> Camera:
    """The camera at ``azimuth`` whose picture holds ``points`` in :data:`BOX` (turned and moved to fit)."""
    distance, target = 2.0, target.copy()
    (left, bottom), (right, top) = BOX
    for _ in range(8):  # perspective: the span shrinks about as 1/distance
        camera = _camera(target, azimuth, distance, aspect)
        ndc = _ndc(camera, points, aspect)
        lo, hi = ndc.min(axis=0), ndc.max(axis=0)
        distance *= max((hi[0] - lo[0]) / (right - left), (hi[1] - lo[1]) / (top - bottom))
        forward = target - np.asarray(camera.eye)
        forward /= np.linalg.norm(forward)
        side = np.cross(forward, camera.up)
        side /= np.linalg.norm(side)
        up = np.cross(side, forward)
        half = distance * math.tan(math.radians(FOV) / 2)
        shift = (lo + hi) / 2 - [(left + right) / 2, (bottom + top) / 2]
        target = target + side * shift[0] * half * aspect + up * shift[1] * half
    return _camera(target, azimuth, distance, aspect)


def _gap(camera: Camera, columns: list[np.ndarray], aspect: float, cube: float) -> float:
    """The smallest horizontal gap (normalised: 2 is the picture's width) between the towers' columns on the screen.

    A column spans its cubes' centres widened by :data:`HALF_WIDTH` cubes on each side.
    """
    view, proj = camera.matrices(int(round(480 * aspect)), 480)
    m = np.asarray(proj).reshape(4, 4, order="F") @ np.asarray(view).reshape(4, 4, order="F")
    spans = []
    for col in columns:
        clip = col @ m[:, :3].T + m[:, 3]
        x, half = clip[:, 0] / clip[:, 3], HALF_WIDTH * cube * m[0, 0] / clip[:, 3].min()
        spans.append((float(x.min()) - half, float(x.max()) + half))
    spans.sort()
    return min((b[0] - a[1] for a, b in zip(spans, spans[1:], strict=False)), default=2.0)


def goal_camera(first: Sequence[Pose], last: Sequence[Pose], config: SimConfig, width: int, height: int,
                between: Sequence[Sequence[Pose]] = ()) -> Camera:
    """The view of a video: every cube of the first and last frames in the picture, the towers apart.

    ``between``: the poses of other frames, whose cubes are kept in the picture as well.
    """
    cube = config.physics.cube_size
    centres = np.asarray([p.position for poses in (first, last, *between) for p in poses], dtype=float)
    points = np.concatenate([centres + [0, 0, cube / 2], centres - [0, 0, cube / 2], [[0.0, 0.0, 0.0]]])
    lo, hi = points.min(axis=0), points.max(axis=0)
    target = (lo + hi) / 2
    aspect = width / height
    best: tuple[float, Camera] | None = None
    for azimuth in AZIMUTHS:  # the first (front first) that leaves a clear gap, else the widest
        camera = _fitted(target, azimuth, points, aspect)
        gap = min(_gap(camera, towers(first, cube), aspect, cube), _gap(camera, towers(last, cube), aspect, cube))
        if gap >= MIN_GAP:
            return camera
        if best is None or gap > best[0]:
            best = (gap, camera)
    assert best is not None
    return best[1]


def top_camera(first: Sequence[Pose], last: Sequence[Pose], width: int, height: int) -> Camera:
    """A view straight down on the cubes of the first and last frames (and the arm's base), the base at the top."""
    centres = np.asarray([p.position for p in (*first, *last)], dtype=float)
    points = np.concatenate([centres[:, :2], [[0.0, 0.0]]])
    lo, hi = points.min(axis=0) - TOP_MARGIN, points.max(axis=0) + TOP_MARGIN
    centre = (lo + hi) / 2
    reach = max((hi[0] - lo[0]) / 2, (hi[1] - lo[1]) / 2 * height / width)
    fov = math.degrees(2 * math.atan(reach / TOP_HEIGHT))
    eye = (float(centre[0]), float(centre[1]), TOP_HEIGHT)
    return Camera(eye=eye, target=(float(centre[0]), float(centre[1]), 0.0), up=(-1.0, 0.0, 0.0), fov=fov,
                  near=0.5, far=TOP_HEIGHT + 1.0)


__all__ = ["goal_camera", "top_camera", "towers"]
