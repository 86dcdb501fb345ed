"""RGB-D perception: what a real colour-and-depth camera could give.

Each fixed camera renders a colour image and a depth image (no segmentation ids). A cube is
known by the ArUco marker printed on its faces (:mod:`.fiducials`): the pixels round each
marker read are back-projected with depth, and the points of every read of a cube, in every
view, are merged. Planes fitted to the points (RANSAC, then least squares) are the cube's
visible faces: the most upward face gives the tilt, a side face the yaw, and each face pins
the centre half a cube behind it. A cube with no read in any view is unseen (never guessed
from its colour, which is cosmetic); so is one read in places too far apart to be one cube.
Optional Gaussian noise on depth (metres, along the optical axis) and colour (8-bit levels)
stands for a real sensor.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from csql_sim.infra.errors import CsqlError
from csql_sim.sim.perception.camera import Camera, capture, perception_cameras, pixel_rays, unproject
from csql_sim.sim.perception.fiducials import (
    READ_LIMITS,
    corner_pixels,
    face_pixels,
    marker_edge,
    plausible,
    read_markers,
)
from csql_sim.sim.perception.poses import BlockObs, Observation, wrap_quarter
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


FACE_FIT = FaceFit()


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


def _frame(faces: list[tuple[np.ndarray, float, np.ndarray]], points: np.ndarray,
           edges: Sequence[np.ndarray] = ()) -> np.ndarray:
    """Three orthonormal cube axes (rows), the most upward first.

    Where the faces pin one axis only, the markers' ``edges`` give the second (else the
    points' footprint does).
    """
    normals = sorted((f[0] for f in faces), key=lambda n: -abs(n[2]))
    axes: list[np.ndarray] = []
    for n in normals:
        v = n - sum((n @ a) * a for a in axes)
        if np.linalg.norm(v) > 0.5:
            axes.append(v / np.linalg.norm(v))
    if not axes:
        axes.append(np.array([0.0, 0.0, 1.0]))
    if len(axes) == 1:
        edge = _edge_axis(axes[0], edges)
        axes.append(_in_plane_axis(axes[0], points) if edge is None else edge)
    if len(axes) == 2:
        axes.append(np.cross(axes[0], axes[1]))
    return np.array(axes)


def _edge_axis(up: np.ndarray, edges: Sequence[np.ndarray]) -> np.ndarray | None:
    """The mean of the marker edges (modulo quarter turns) in the plane normal to ``up``, or None."""
    total: np.ndarray | None = None
    for e in edges:
        if abs(e @ up) > 0.5:  # an edge along ``up`` says nothing of the turn about it
            continue
        v = e - (e @ up) * up
        v /= np.linalg.norm(v)
        if total is not None:
            turns = (v, -v, np.cross(up, v), -np.cross(up, v))
            v = max(turns, key=lambda t: float(t @ total))
        total = v if total is None else total + v
    return None if total is None else total / np.linalg.norm(total)


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
                  noise: float = 0.0, edges: Sequence[np.ndarray] = ()) -> BlockObs:
    """Centre, tilt and yaw of a cube from its visible surface points (world frame).

    Fitted faces give a first frame and centre (each face pins the centre half a cube
    behind it; an axis no face pins takes the points' centroid); a cube model fitted to
    all the points refines both. ``edges``: unit edge directions of the markers read on it.
    """
    faces = fit_faces(points, eyes, rng, noise)
    axes = _frame(faces, points, edges)
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


Render = Callable[[Camera], tuple[np.ndarray, np.ndarray]]
"""A camera's colour image (h, w, 3 uint8) and depth buffer (h, w) of the scene now."""


@dataclass
class Reads:
    """What the cameras saw of each cube: its face points, the eyes that saw them and the reads' centres."""

    points: list[list[np.ndarray]]
    eyes: list[list[np.ndarray]]
    centres: list[list[np.ndarray]]
    edges: list[list[np.ndarray]]

    @classmethod
    def empty(cls, n: int) -> Reads:
        """No reads of n cubes."""
        return cls(*([[] for _ in range(n)] for _ in range(4)))

    def count(self, i: int) -> int:
        """The plausible reads of cube i."""
        return len(self.centres[i])


def read_view(reads: Reads, camera: Camera, rgb: np.ndarray, depth: np.ndarray, size: float) -> None:
    """Add one view's plausible marker reads to ``reads``."""
    eye = np.asarray(camera.eye, dtype=float)
    for read in read_markers(rgb, len(reads.points)):
        rows, cols = face_pixels(read, depth.shape)
        if len(rows) < READ_LIMITS.min_pixels:
            continue
        if not plausible(unproject(camera, depth, *corner_pixels(read, depth.shape)), size):
            continue
        points = unproject(camera, depth, rows, cols)
        near = np.linalg.norm(points - np.median(points, axis=0), axis=1) < READ_LIMITS.face_radius * size
        points = points[near]  # not the pixels past the face's edge (the table or the sky behind)
        if len(points) < READ_LIMITS.min_pixels:
            continue
        normal, offset = _plane(points)
        edge = marker_edge(read, *pixel_rays(camera, depth.shape, read.corners), normal, offset)
        if edge is not None:
            reads.edges[read.cube].append(edge)
        reads.points[read.cube].append(points)
        reads.eyes[read.cube].append(np.broadcast_to(eye, points.shape))
        reads.centres[read.cube].append(points.mean(axis=0))


def locate_cubes(render: Render, cameras: tuple[Camera, ...], n: int, size: float,
                 noise: CameraNoise = NO_NOISE, rng: np.random.Generator | None = None) -> tuple[BlockObs, ...]:
    """Every cube's estimate from the views' marker reads; a cube no view read (or read apart) is unseen.

    Args:
        render: the colour and depth images of a camera.
        cameras: the views.
        n: cubes 0..n-1 (marker ids).
        size: their edge, m.
        noise: sensor noise to add.
        rng: draws the noise and the RANSAC samples (a fixed generator when None).
    """
    rng = rng if rng is not None else np.random.default_rng(0)
    reads = Reads.empty(n)
    for camera in cameras:
        rgb, depth = render(camera)
        if noise.active:
            rgb, depth = add_noise(rgb, depth, camera, noise, rng)
        read_view(reads, camera, rgb, depth, size)
    blocks = []
    for i in range(n):
        centres = np.array(reads.centres[i]).reshape(-1, 3)
        apart = len(centres) > 1 and np.ptp(centres, axis=0).max() > 1.5 * size  # one id, two places: no guess
        if not len(centres) or apart:
            blocks.append(BlockObs((0.0, 0.0, -1.0), None, 0.0, visible=False, reads=len(centres)))
            continue
        seen = estimate_cube(np.concatenate(reads.points[i]), np.concatenate(reads.eyes[i]), size, rng, noise.depth,
                             reads.edges[i])
        blocks.append(replace(seen, reads=len(centres)))
    return tuple(blocks)


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
    cameras = perception_cameras(scene.n) if cameras is None else cameras
    size = scene.config.physics.cube_size

    def render(camera: Camera) -> tuple[np.ndarray, np.ndarray]:
        return capture(scene, camera, camera.width, camera.height)[:2]

    blocks = locate_cubes(render, cameras, scene.n, size, noise, rng)
    return Observation(blocks, tuple(panda.ee_position()), panda.finger_width(), size)


__all__ = ["CameraNoise", "NO_NOISE", "estimate_cube", "locate_cubes", "observe_rgbd"]
