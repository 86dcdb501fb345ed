"""RGB-D perception: what a real colour-and-depth camera could give.

Each fixed camera renders a colour image and a depth image (no segmentation ids). The
cubes are segmented by colour (hue and saturation of their known paint), their pixels
back-projected with depth, and the points of every view merged. Planes fitted to the
points (RANSAC, then least squares) are the cube's visible faces: the most upward face
gives the tilt, a side face the yaw, and each face pins the centre half a cube behind it.
Optional Gaussian noise on depth (metres, along the optical axis) and colour (8-bit
levels) stands for a real sensor.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csql_sim.infra.errors import CsqlError
from csql_sim.sim.perception.camera import Camera, capture, perception_cameras, unproject
from csql_sim.sim.perception.poses import BlockObs, Observation, wrap_quarter
from csql_sim.sim.world.config import COLOURS
from csql_sim.sim.world.robot import Panda
from csql_sim.sim.world.scene import Scene


@dataclass(frozen=True)
class CameraNoise:
    """Sensor noise of the perception cameras.

    Attributes:
        depth: standard deviation of the depth along the optical axis, m (>= 0).
        colour: standard deviation of every colour channel, 8-bit levels (>= 0).
    """

    depth: float = 0.0
    colour: float = 0.0

    def __post_init__(self) -> None:
        for name in ("depth", "colour"):
            value = getattr(self, name)
            if not math.isfinite(value) or value < 0:
                raise CsqlError(f"camera noise {name} must be a finite number >= 0, got {value}")

    @property
    def active(self) -> bool:
        """True when any noise is added."""
        return self.depth > 0 or self.colour > 0


NO_NOISE = CameraNoise()


@dataclass(frozen=True)
class SegmentationLimits:
    """Colour segmentation: a pixel belongs to the cube of the nearest paint hue."""

    hue: float = 10.0  # degrees from the paint's hue
    saturation: float = 0.5  # least saturation of a cube pixel (table and arm are greyer)
    value: float = 0.12  # least brightness of a cube pixel


@dataclass(frozen=True)
class FaceFit:
    """Plane fitting of cube faces."""

    inlier: float = 0.0025  # m from the plane, plus 2.5 x the depth noise
    min_points: int = 8  # fewest points of a face
    hypotheses: int = 60  # RANSAC triples per face
    orthogonal: float = 0.35  # a new face's |cos| to every found face is below this ...
    parallel: float = 0.94  # ... or above this (the opposite face)
    min_pixels: int = 4  # fewer cube pixels than this in every view: out of sight
    refine_iterations: int = 12  # Gauss-Newton steps of the cube model fit
    damping: float = 1e-4  # Levenberg damping of those steps (keeps unseen directions still)


SEGMENTATION = SegmentationLimits()
FACE_FIT = FaceFit()


def hue_saturation_value(rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hue (degrees), saturation and value (0..1) of an (..., 3) uint8 image."""
    c = rgb.astype(np.float64) / 255.0
    mx, mn = c.max(axis=-1), c.min(axis=-1)
    span = np.where(mx > mn, mx - mn, 1.0)
    r, g, b = c[..., 0], c[..., 1], c[..., 2]
    hue = np.where(mx == r, (g - b) / span, np.where(mx == g, 2.0 + (b - r) / span, 4.0 + (r - g) / span))
    hue = (hue * 60.0) % 360.0
    sat = np.where(mx > 0, (mx - mn) / np.where(mx > 0, mx, 1.0), 0.0)
    return hue, sat, mx


def paint_hues(n: int) -> np.ndarray:
    """The hue (degrees) of each of the n cubes' paint."""
    return np.array([hue_saturation_value(np.array([[int(round(255 * v)) for v in COLOURS[i][:3]]],
                                                   dtype=np.uint8))[0][0] for i in range(n)])


def segment(rgb: np.ndarray, hues: np.ndarray, limits: SegmentationLimits = SEGMENTATION) -> np.ndarray:
    """Label image: the cube index of every pixel, -1 for anything else."""
    labels = np.full(rgb.shape[:2], -1, dtype=np.int64)
    mx = rgb.max(axis=-1).astype(np.int32)
    mn = rgb.min(axis=-1).astype(np.int32)
    vivid = (mx - mn > limits.saturation * mx) & (mx > limits.value * 255)
    if not vivid.any():
        return labels
    hue = hue_saturation_value(rgb[vivid])[0]
    diff = np.abs((hue[:, None] - hues + 180.0) % 360.0 - 180.0)
    nearest = np.argmin(diff, axis=1)
    labels[vivid] = np.where(diff[np.arange(len(hue)), nearest] < limits.hue, nearest, -1)
    return labels


def add_noise(rgb: np.ndarray, depth: np.ndarray, camera: Camera, noise: CameraNoise,
              rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """The image pair with Gaussian colour noise and metric depth noise added."""
    if noise.colour > 0:
        rgb = np.clip(np.rint(rgb + rng.normal(0.0, noise.colour, rgb.shape)), 0, 255).astype(np.uint8)
    if noise.depth > 0:
        near, far = camera.near, camera.far
        metric = far * near / (far - (far - near) * depth)
        metric = np.clip(metric + rng.normal(0.0, noise.depth, depth.shape), near, far)
        depth = (far - far * near / metric) / (far - near)
    return rgb, depth


def _plane(points: np.ndarray) -> tuple[np.ndarray, float]:
    """Least-squares plane (unit normal, offset) of points."""
    centre = points.mean(axis=0)
    normal = np.linalg.svd(points - centre, full_matrices=False)[2][2]
    return normal, float(normal @ centre)


def fit_faces(points: np.ndarray, eyes: np.ndarray, rng: np.random.Generator, noise: float = 0.0,
              fit: FaceFit = FACE_FIT) -> list[tuple[np.ndarray, float, np.ndarray]]:
    """Up to three visible faces, orthogonal or opposite to each other: (outward normal, offset, inlier mask) each."""
    thr = fit.inlier + 2.5 * noise
    faces: list[tuple[np.ndarray, float, np.ndarray]] = []
    free = np.ones(len(points), dtype=bool)
    while len(faces) < 3 and free.sum() >= fit.min_points:
        idx = np.flatnonzero(free)
        tri = points[idx[rng.integers(len(idx), size=(fit.hypotheses, 3))]]
        normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        norm = np.linalg.norm(normals, axis=1)
        good = norm > 1e-9
        for n, _, _ in faces:
            cos = np.abs(normals @ n) / np.maximum(norm, 1e-12)
            good &= (cos < fit.orthogonal) | (cos > fit.parallel)
        if not good.any():
            break
        normals = normals[good] / norm[good, None]
        offsets = np.einsum("ij,ij->i", normals, tri[good, 0])
        counts = (np.abs(points[idx] @ normals.T - offsets) < thr).sum(axis=0)
        best = int(np.argmax(counts))
        if counts[best] < fit.min_points:
            break
        inliers = free & (np.abs(points @ normals[best] - offsets[best]) < thr)
        normal, offset = _plane(points[inliers])
        inliers = free & (np.abs(points @ normal - offset) < thr)
        if inliers.sum() < fit.min_points:
            break
        normal, offset = _plane(points[inliers])
        if normal @ (eyes[inliers].mean(axis=0) - points[inliers].mean(axis=0)) < 0:  # outward: towards the camera
            normal, offset = -normal, -offset
        faces.append((normal, offset, inliers))
        free &= ~inliers
    return faces


def _frame(faces: list[tuple[np.ndarray, float, np.ndarray]], points: np.ndarray) -> np.ndarray:
    """Three orthonormal cube axes (rows), the most upward first."""
    normals = sorted((f[0] for f in faces), key=lambda n: -abs(n[2]))
    axes: list[np.ndarray] = []
    for n in normals:
        v = n - sum((n @ a) * a for a in axes)
        if np.linalg.norm(v) > 0.5:
            axes.append(v / np.linalg.norm(v))
    if not axes:
        axes.append(np.array([0.0, 0.0, 1.0]))
    if len(axes) == 1:
        axes.append(_in_plane_axis(axes[0], points))
    if len(axes) == 2:
        axes.append(np.cross(axes[0], axes[1]))
    return np.array(axes)


def _in_plane_axis(up: np.ndarray, points: np.ndarray) -> np.ndarray:
    """An edge direction of the points' footprint in the plane normal to ``up`` (least bounding box)."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = helper - (helper @ up) * up
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(up, e1)
    uv = np.stack([points @ e1, points @ e2], axis=1)
    angles = np.radians(np.arange(0.0, 90.0, 2.0))
    dirs = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    a, b = uv @ dirs.T, uv @ np.stack([-dirs[:, 1], dirs[:, 0]], axis=1).T
    area = np.ptp(a, axis=0) * np.ptp(b, axis=0)
    k = int(np.argmin(area))
    return dirs[k, 0] * e1 + dirs[k, 1] * e2


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def refine_pose(points: np.ndarray, axes: np.ndarray, centre: np.ndarray, size: float, noise: float = 0.0,
                fit: FaceFit = FACE_FIT) -> tuple[np.ndarray, np.ndarray]:
    """Fit a cube of edge ``size`` to surface points: (axes as rows, centre) by Gauss-Newton.

    Every point is assigned to the face nearest to it (the largest local coordinate), its
    residual is its distance from that face's plane; points far off any face are ignored.
    """
    half = size / 2
    cut = 2.0 * (fit.inlier + 2.5 * noise)
    for _ in range(fit.refine_iterations):
        local = (points - centre) @ axes.T
        j = np.argmax(np.abs(local), axis=1)
        idx = np.arange(len(points))
        sign = np.sign(local[idx, j])
        r = sign * local[idx, j] - half
        keep = np.abs(r) < cut
        if keep.sum() < 6:
            break
        e = np.eye(3)[j[keep]]
        jac = -sign[keep, None] * np.hstack([e, np.cross(local[keep], e)])
        step = np.linalg.solve(jac.T @ jac + fit.damping * np.eye(6), -jac.T @ r[keep])
        centre = centre + axes.T @ step[:3]
        u, _, vt = np.linalg.svd((np.eye(3) - _skew(step[3:])) @ axes)
        axes = u @ vt
        if np.linalg.norm(step) < 1e-6:
            break
    return axes, centre


def estimate_cube(points: np.ndarray, eyes: np.ndarray, size: float, rng: np.random.Generator,
                  noise: float = 0.0) -> BlockObs:
    """Centre, tilt and yaw of a cube from its visible surface points (world frame).

    Fitted faces give a first frame and centre (each face pins the centre half a cube
    behind it; an axis no face pins takes the points' centroid); a cube model fitted to
    all the points refines both.
    """
    faces = fit_faces(points, eyes, rng, noise)
    axes = _frame(faces, points)
    rows, rhs = [], []
    for normal, offset, _ in faces:
        rows.append(normal)
        rhs.append(offset - size / 2)
    centroid = points.mean(axis=0)
    for a in axes:
        if all(abs(a @ f[0]) < 0.9 for f in faces):
            rows.append(a)
            rhs.append(float(a @ centroid))
    centre = np.linalg.lstsq(np.array(rows), np.array(rhs), rcond=None)[0]
    if not faces:
        return BlockObs((float(centre[0]), float(centre[1]), float(centre[2])), None, 0.0)
    axes, centre = refine_pose(points, axes, centre, size, noise)
    k = int(np.argmax(np.abs(axes[:, 2])))
    tilt = math.acos(min(1.0, abs(float(axes[k, 2]))))
    side = axes[(k + 1) % 3]
    yaw = wrap_quarter(math.atan2(float(side[1]), float(side[0])))
    frame = tuple(tuple(float(v) for v in a) for a in axes)
    return BlockObs((float(centre[0]), float(centre[1]), float(centre[2])), tilt, yaw, axes=frame)


def observe_rgbd(scene: Scene, panda: Panda, cameras: tuple[Camera, ...] | None = None,
                 noise: CameraNoise = NO_NOISE, rng: np.random.Generator | None = None) -> Observation:
    """Camera-mode observation from colour and depth images only (plus the arm's proprioception).

    Args:
        scene: the physical scene (rendered, never read for poses).
        panda: the arm: grasp point and finger opening by proprioception.
        cameras: the fixed perception cameras (default: :func:`~csql_sim.sim.perception.camera.perception_cameras` n).
        noise: sensor noise to add.
        rng: draws the noise and the RANSAC samples (a fixed generator when None).
    """
    rng = rng if rng is not None else np.random.default_rng(0)
    cameras = perception_cameras(scene.n) if cameras is None else cameras
    size = scene.config.physics.cube_size
    hues = paint_hues(scene.n)
    clouds: list[list[np.ndarray]] = [[] for _ in range(scene.n)]
    eyes: list[list[np.ndarray]] = [[] for _ in range(scene.n)]
    for camera in cameras:
        rgb, depth, _ = capture(scene, camera, camera.width, camera.height)
        if noise.active:
            rgb, depth = add_noise(rgb, depth, camera, noise, rng)
        labels = segment(rgb, hues)
        for i in range(scene.n):
            rows, cols = np.nonzero(labels == i)
            if len(rows):
                clouds[i].append(unproject(camera, depth, rows, cols))
                eyes[i].append(np.broadcast_to(np.asarray(camera.eye, dtype=float), (len(rows), 3)))
    blocks = []
    for i in range(scene.n):
        count = sum(len(c) for c in clouds[i])
        if count < FACE_FIT.min_pixels:
            blocks.append(BlockObs((0.0, 0.0, -1.0), None, 0.0, visible=False))
            continue
        blocks.append(estimate_cube(np.concatenate(clouds[i]), np.concatenate(eyes[i]), size, rng, noise.depth))
    return Observation(tuple(blocks), tuple(panda.ee_position()), panda.finger_width(), size)


__all__ = ["CameraNoise", "NO_NOISE", "estimate_cube", "observe_rgbd", "segment"]
