"""Cameras: the fixed perception camera (segmentation + depth) and rendering views."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csql_sim.sim.perception import BlockObs, Observation, Tolerances
from csql_sim.sim.robot import Panda
from csql_sim.sim.scene import Scene, projection_matrix, view_matrix


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


PERCEPTION_CAMERA = Camera()
PERCEPTION_CAMERAS = (
    PERCEPTION_CAMERA,  # in front of the table, facing the robot
    Camera(eye=(0.55, 0.85, 0.6), target=(0.5, 0.0, 0.05)),  # from the left
    Camera(eye=(0.55, -0.85, 0.6), target=(0.5, 0.0, 0.05)),  # from the right
)
"""Three views; each cube is located in the view that sees most of it."""
RENDER_CAMERA = Camera(eye=(1.4, 0.6, 0.7), target=(0.3, 0.0, 0.3), fov=50.0, width=640, height=480)
"""The video view: the whole arm (base to raised hand) and the cubes, from the front right."""
CAMERA_TOLERANCES = Tolerances(stack_z=0.012, stack_xy=0.025, table_z=0.012, hold_dist=0.03)
"""Camera estimates are coarser than poses: slightly wider tolerances."""


def capture(scene: Scene, camera: Camera, width: int, height: int, segmentation: bool = False,
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """RGB (h, w, 3 uint8), depth buffer and segmentation ids from the TinyRenderer."""
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


def observe_camera(scene: Scene, panda: Panda, cameras: tuple[Camera, ...] = PERCEPTION_CAMERAS) -> Observation:
    """Camera-mode observation: cube centres estimated from segmentation and depth.

    Every camera renders a segmentation mask and a depth image; each cube is located in
    the view that shows most of its pixels. There its visible surface points are
    back-projected: the top is the highest visible point, the centre lies half a cube
    below it, and horizontally at the points' centroid pushed a quarter cube away from
    the camera (the visible faces face it). The gripper's grasp point and opening come
    from proprioception.
    """
    size = scene.config.physics.cube_size
    views = []
    for camera in cameras:
        _, depth, seg = capture(scene, camera, camera.width, camera.height, segmentation=True)
        views.append((camera, depth, seg))
    blocks = []
    for i in range(scene.n):
        body = scene.block_body(i)
        camera, depth, seg = max(views, key=lambda v: int(np.count_nonzero(v[2] == body)))
        rows, cols = np.nonzero(seg == body)
        if len(rows) < 4:
            blocks.append(BlockObs((0.0, 0.0, -1.0), None, 0.0, visible=False))
            continue
        pts = unproject(camera, depth, rows, cols)
        top = float(np.percentile(pts[:, 2], 98))
        centroid = pts[:, :2].mean(axis=0)
        away = centroid - np.asarray(camera.eye[:2])
        away /= max(float(np.linalg.norm(away)), 1e-9)
        xy = centroid + away * size / 4
        blocks.append(BlockObs((float(xy[0]), float(xy[1]), top - size / 2), None, 0.0))
    return Observation(tuple(blocks), tuple(panda.ee_position()), panda.finger_width(), size)
