"""Face reads: one decoded marker, placed in depth, is one face of one cube with its full frame.

:func:`read_view` turns a view's marker reads (:mod:`.fiducials`) into :class:`FaceRead` records:
the face's points back-projected with depth, the plane fitted to them (its outward normal and
offset) and the marker's edge in that plane. A face read alone gives the cube's whole frame
(normal, edge, and their cross product); :func:`cube_frame` merges the frames of every read of
a cube, each matched to the first by quarter turns, and :func:`cube_centre` places the centre
half a cube behind every read face (along an axis no read face pins, at the points' centroid).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csql_sim.sim.perception.camera import Camera, pixel_rays, unproject
from csql_sim.sim.perception.fiducials import (
    READ_LIMITS,
    ReadLimits,
    corner_pixels,
    face_pixels,
    marker_edge,
    plausible,
    read_markers,
)

PINNED = 0.9
"""A frame axis is pinned by a read face whose normal is this parallel to it (|cos|)."""


@dataclass(frozen=True)
class FaceRead:
    """One marker read placed in depth.

    Attributes:
        cube: the cube's index (the marker's id).
        points: the face's points (k, 3), world frame, m.
        normal: the face's outward unit normal (towards the camera).
        offset: ``normal . p`` of the face's plane, m.
        edge: a unit edge direction of the marker, in the face's plane.
    """

    cube: int
    points: np.ndarray
    normal: np.ndarray
    offset: float
    edge: np.ndarray

    @property
    def centre(self) -> np.ndarray:
        """The mean of the face's points."""
        return self.points.mean(axis=0)

    def frame(self) -> np.ndarray:
        """The cube's axes (rows) as this face sees them: normal, edge, and normal x edge."""
        return np.array([self.normal, self.edge, np.cross(self.normal, self.edge)])


def fit_plane(points: np.ndarray, noise: float) -> tuple[np.ndarray, float, np.ndarray]:
    """Least-squares plane (unit normal, offset) of points, and the mask of the points kept.

    The first fit takes the three quarters of the points nearest their median point; each
    refit keeps the points within 2 mm (plus 3 x the depth noise) of the last plane.
    """
    spread = np.linalg.norm(points - np.median(points, axis=0), axis=1)
    keep = spread <= np.percentile(spread, 75)
    for _ in range(3):
        centre = points[keep].mean(axis=0)
        normal = np.linalg.svd(points[keep] - centre, full_matrices=False)[2][2]
        offset = float(normal @ centre)
        keep = np.abs(points @ normal - offset) < 0.002 + 3.0 * noise
        if keep.sum() < 3:
            keep[:] = True
            break
    return normal, offset, keep


def read_view(camera: Camera, rgb: np.ndarray, depth: np.ndarray, n: int, size: float,
              noise: float = 0.0, limits: ReadLimits = READ_LIMITS) -> list[FaceRead]:
    """The plausible face reads of cubes 0..n-1 in one view (``noise``: the depth noise, m).

    ``limits``: how markers are decoded and their reads checked (:mod:`.fiducials`).
    """
    eye = np.asarray(camera.eye, dtype=float)
    out = []
    for read in read_markers(rgb, n, limits):
        rows, cols = face_pixels(read, depth.shape, limits)
        if len(rows) < limits.min_pixels:
            continue
        if not plausible(unproject(camera, depth, *corner_pixels(read, depth.shape, limits)), size, limits):
            continue
        points = unproject(camera, depth, rows, cols)
        near = np.linalg.norm(points - np.median(points, axis=0), axis=1) < limits.face_radius * size
        points = points[near]  # not the pixels past the face's edge (the table or the sky behind)
        if len(points) < limits.min_pixels:
            continue
        normal, offset, keep = fit_plane(points, noise)
        if normal @ (eye - points[keep].mean(axis=0)) < 0:  # outward: towards the camera
            normal, offset = -normal, -offset
        edge = marker_edge(read, *pixel_rays(camera, depth.shape, read.corners), normal, offset)
        if edge is not None:
            out.append(FaceRead(read.cube, points[keep], normal, offset, edge))
    return out


def cube_frame(faces: list[FaceRead]) -> np.ndarray:
    """The cube's axes (orthonormal rows) from its face reads, weighted by their points."""
    reference = faces[0].frame()
    total = np.zeros((3, 3))
    for face in faces:
        frame = face.frame()
        cos = reference @ frame.T
        for i in range(3):  # the axis of this read most parallel to each reference axis, signed alike
            j = int(np.argmax(np.abs(cos[i])))
            total[i] += np.sign(cos[i, j]) * frame[j] * len(face.points)
    u, _, vt = np.linalg.svd(total)
    return u @ vt


def cube_centre(faces: list[FaceRead], axes: np.ndarray, size: float) -> np.ndarray:
    """The centre: half a cube behind each read face; along an axis no face pins, the points' centroid."""
    rows = [f.normal for f in faces]
    rhs = [f.offset - size / 2 for f in faces]
    centroid = np.concatenate([f.points for f in faces]).mean(axis=0)
    for axis in axes:
        if all(abs(axis @ f.normal) < PINNED for f in faces):
            rows.append(axis)
            rhs.append(float(axis @ centroid))
    return np.linalg.lstsq(np.array(rows), np.array(rhs), rcond=None)[0]


__all__ = ["FaceRead", "cube_centre", "cube_frame", "fit_plane", "read_view"]
