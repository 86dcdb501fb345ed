"""Cameras: the fixed perception cameras (colour + depth, see rgbd.py) and rendering views."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csql_sim.sim.perception.poses import Tolerances
from csql_sim.sim.world.scene import Scene, projection_matrix, view_matrix


@dataclass(frozen=True)
class Camera:
    """A pinhole camera looking from ``eye`` at ``target``."""

    eye: tuple[float, float, float] = (1.15, 0.0, 0.75)  # m
    target: tuple[float, float, float] = (0.5, 0.0, 0.05)  # m
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    fov: float = 45.0  # vertical field of view, degrees
    width: int = 320  # pixels
    height: int = 240  # pixels
    near: float = 0.1  # m
    far: float = 3.0  # m

    def matrices(self, width: int | None = None, height: int | None = None) -> tuple[list[float], list[float]]:
        """The pybullet view and projection matrices (column-major lists)."""
        w, h = width or self.width, height or self.height
        return view_matrix(self.eye, self.target, self.up), projection_matrix(self.fov, w / h, self.near, self.far)


PERCEPTION_CAMERA = Camera(width=1280, height=960)
PERCEPTION_CAMERAS = (
    PERCEPTION_CAMERA,  # in front of the table, facing the robot
    Camera(eye=(0.55, 0.85, 0.6), target=(0.5, 0.0, 0.05), width=1280, height=960),  # from the left
    Camera(eye=(0.55, -0.85, 0.6), target=(0.5, 0.0, 0.05), width=1280, height=960),  # from the right
)
"""Three views of up to six cubes, each cube placed from the marker reads of all of them.

1280 x 960: a 4 cm face 0.9 m away spans about 56 pixels, its marker's cells 6 pixels each. (At
640 x 480, 3 pixels a cell, a tilted or dropped cube at the bottom of a tower went unread in perturbed
episodes.)"""
RENDER_CAMERA = Camera(eye=(1.4, 0.6, 0.7), target=(0.3, 0.0, 0.3), fov=50.0, width=640, height=480)
"""The video view: the whole arm (base to raised hand) and the cubes, from the front right."""
WIDE_PERCEPTION_CAMERAS = (
    Camera(eye=(1.45, 0.0, 1.0), target=(0.42, 0.0, 0.12), fov=55.0, width=1280, height=960),  # in front, further back
    Camera(eye=(0.4, 1.25, 0.95), target=(0.42, 0.0, 0.12), fov=55.0, width=1280, height=960),  # from the left
    Camera(eye=(0.4, -1.25, 0.95), target=(0.42, 0.0, 0.12), fov=55.0, width=1280, height=960),  # from the right
)
"""The views of 7 or more cubes (:func:`perception_cameras`): the whole arc of places, and a tower of ten
at either end of it, in every view. 1280 x 960: a 4 cm face 1.3 m away spans about 30 pixels
(at 960 x 720 some cubes of a ten-cube scene were read in one view only, at 480 x 360 none)."""
WIDE_RENDER_CAMERA = RENDER_CAMERA
"""The video view of 7..10 cubes (:func:`render_camera`)."""


def perception_cameras(n: int) -> tuple[Camera, ...]:
    """The perception cameras of an n-cube scene: :data:`PERCEPTION_CAMERAS` for n <= 6."""
    return PERCEPTION_CAMERAS if n <= 6 else WIDE_PERCEPTION_CAMERAS


FALLBACK_CAMERAS = (
    Camera(eye=(0.75, 0.0, 1.15), target=(0.5, 0.0, 0.05), width=1280, height=960),  # from above
    Camera(eye=(0.2, 0.75, 0.9), target=(0.5, 0.0, 0.05), width=1280, height=960),  # from above on the left
    Camera(eye=(0.2, -0.75, 0.9), target=(0.5, 0.0, 0.05), width=1280, height=960),  # from above on the right
)
"""Further views of up to six cubes, rendered only for a cube no usual view read (:func:`fallback_cameras`):
from above (over a cube walled in or hidden behind a tower) and from the arm's side."""
WIDE_FALLBACK_CAMERAS = (
    Camera(eye=(1.2, 0.0, 1.6), target=(0.3, 0.0, 0.1), fov=55.0, width=1280, height=960),  # in front, high
    Camera(eye=(-1.1, 0.6, 1.2), target=(-0.1, 0.0, 0.15), fov=55.0, width=1280, height=960),  # behind, left
    Camera(eye=(-1.1, -0.6, 1.2), target=(-0.1, 0.0, 0.15), fov=55.0, width=1280, height=960),  # behind, right
    Camera(eye=(0.1, 1.2, 1.5), target=(0.1, 0.0, 0.1), fov=55.0, width=1280, height=960),  # left, high
    Camera(eye=(0.1, -1.2, 1.5), target=(0.1, 0.0, 0.1), fov=55.0, width=1280, height=960),  # right, high
)
"""Further views of 7 or more cubes (:func:`fallback_cameras`): higher than the usual ones (over the
towers in front of a cube) and from behind the arm (the far side of the ring of thirty places)."""


def fallback_cameras(n: int) -> tuple[Camera, ...]:
    """The views perception renders, one at a time, only while a cube is unread by the usual ones."""
    return FALLBACK_CAMERAS if n <= 6 else WIDE_FALLBACK_CAMERAS


def render_camera(n: int) -> Camera:
    """The video view of an n-cube scene: :data:`RENDER_CAMERA` for n <= 6."""
    return RENDER_CAMERA if n <= 6 else WIDE_RENDER_CAMERA


CAMERA_TOLERANCES = Tolerances(stack_z=0.012, stack_xy=0.025, table_z=0.012, hold_dist=0.03)
"""Camera estimates are coarser than poses: slightly wider tolerances."""


def capture(scene: Scene, camera: Camera, width: int, height: int, segmentation: bool = False,
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """RGB (h, w, 3 uint8), depth buffer and segmentation ids (rendering tools only) from the TinyRenderer."""
    view, proj = camera.matrices(width, height)
    return scene.render(view, proj, width, height, segmentation)


def unproject(camera: Camera, depth: np.ndarray, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """World points (k, 3) of the pixels (rows, cols) of a depth buffer."""
    h, w = depth.shape
    view, proj = camera.matrices(w, h)
    pv = np.asarray(proj).reshape(4, 4, order="F") @ np.asarray(view).reshape(4, 4, order="F")
    inv = np.linalg.inv(pv)
    x = 2.0 * (cols + 0.5) / w - 1.0
    y = 1.0 - 2.0 * (rows + 0.5) / h
    z = 2.0 * depth[rows, cols] - 1.0
    pts = inv @ np.stack([x, y, z, np.ones_like(x)])
    return (pts[:3] / pts[3]).T


def pixel_rays(camera: Camera, shape: tuple[int, int], xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Origins and unit directions (k, 3 each) of the rays through sub-pixel points ``xy`` (k, 2: x, y)."""
    h, w = shape
    view, proj = camera.matrices(w, h)
    inv = np.linalg.inv(np.asarray(proj).reshape(4, 4, order="F") @ np.asarray(view).reshape(4, 4, order="F"))
    x = 2.0 * (xy[:, 0] + 0.5) / w - 1.0
    y = 1.0 - 2.0 * (xy[:, 1] + 0.5) / h
    ends = []
    for z in (-1.0, 1.0):
        pts = inv @ np.stack([x, y, np.full_like(x, z), np.ones_like(x)])
        ends.append((pts[:3] / pts[3]).T)
    direction = ends[1] - ends[0]
    return ends[0], direction / np.linalg.norm(direction, axis=1, keepdims=True)
