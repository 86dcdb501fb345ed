"""Reading the cubes' markers: which cube a patch of a colour image is, and which pixels are its face.

Every cube carries its ArUco marker on all six faces (:mod:`csql_sim.sim.world.markers`).
:func:`read_markers` finds the markers of a colour image with OpenCV's detector; a read is
the marker's id (the cube's index) and its four corners. :func:`face_pixels` gives the pixels
of the face round a read (the marker grown into its quiet zone), whose depth places the
face; :func:`plausible` checks that the read's corners, back-projected, are as far apart
as a marker printed on a cube is. A marker the detector cannot decode is no read at all:
the cube stays unknown in that image, never guessed.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import cv2
import numpy as np

from csql_sim.sim.world.markers import MARKER_LAYOUT, dictionary


@dataclass(frozen=True)
class ReadLimits:
    """How reads are turned into face pixels and checked.

    Attributes:
        grow: face pixels are the marker's quadrilateral grown about its centre by this factor (1..1.4:
            beyond ``1 / marker_fraction`` it would spill off the face).
        shrink: the corners checked by :func:`plausible` are pulled this far towards the centre (0..1).
        side_tolerance: a back-projected marker side may differ from the printed one by this fraction.
        min_pixels: a read with fewer face pixels than this is dropped.
        face_radius: face pixels further than this many cube edges from their median point are dropped
            (a face's points lie within 0.71 of it; beyond are the pixels behind an edge).
        min_perimeter: the detector's least marker perimeter, as a fraction of the image's larger side.
        pixels_per_cell: the detector samples each cell of a marker at this many pixels (OpenCV's default 4).
        error_correction: the share of the dictionary's correctable bits the detector may correct (0..1;
            OpenCV's default 0.6): less trades no reads here for fewer chances of a wrong id.
    """

    grow: float = 1.3
    shrink: float = 0.8
    side_tolerance: float = 0.35
    min_pixels: int = 12
    face_radius: float = 0.8
    min_perimeter: float = 0.01
    pixels_per_cell: int = 8
    error_correction: float = 0.3


READ_LIMITS = ReadLimits()

RETRY_LIMITS = ReadLimits(pixels_per_cell=6)
"""A second decoding of a view's image, only for a cube no read found in it: the marker's cells
sampled at 6 pixels, not 8. A sampling can miss one marker that another reads: in a 20-cube
scene a green cube's marker, in plain view of the front camera, decoded at 4, 6 and 10 pixels
a cell and not at 8, and perception called the cube unseen. Everything else is as
:data:`READ_LIMITS` (the error correction too)."""


@dataclass(frozen=True)
class MarkerRead:
    """One decoded marker in one image.

    Attributes:
        cube: the marker's id, the cube's index.
        corners: (4, 2) pixel coordinates (x, y) of its corners, in the detector's order.
    """

    cube: int
    corners: np.ndarray

    @property
    def centre(self) -> np.ndarray:
        """The mean of the corners (x, y)."""
        return self.corners.mean(axis=0)


@cache
def _detector(limits: ReadLimits) -> cv2.aruco.ArucoDetector:
    params = cv2.aruco.DetectorParameters()
    params.minMarkerPerimeterRate = limits.min_perimeter
    params.perspectiveRemovePixelPerCell = limits.pixels_per_cell
    params.errorCorrectionRate = limits.error_correction
    params.cornerRefinementMethod = cv2.aruco.CORNER_REFINE_CONTOUR  # corners from the fitted border lines
    return cv2.aruco.ArucoDetector(dictionary(), params)


def read_markers(rgb: np.ndarray, n: int, limits: ReadLimits = READ_LIMITS) -> list[MarkerRead]:
    """The reads of markers of cubes 0..n-1 in an RGB image (other ids are ignored)."""
    gray = cv2.cvtColor(np.ascontiguousarray(rgb), cv2.COLOR_RGB2GRAY)
    corners, ids, _ = _detector(limits).detectMarkers(gray)
    if ids is None:
        return []
    return [MarkerRead(int(i), np.asarray(c, dtype=np.float64).reshape(4, 2))
            for c, i in zip(corners, np.asarray(ids).ravel(), strict=True) if 0 <= int(i) < n]


def face_pixels(read: MarkerRead, shape: tuple[int, int], limits: ReadLimits = READ_LIMITS,
                ) -> tuple[np.ndarray, np.ndarray]:
    """Rows and columns of the face pixels round a read: its corners grown by ``limits.grow``."""
    grow = min(limits.grow, 0.95 / MARKER_LAYOUT.marker_fraction)
    quad = read.centre + grow * (read.corners - read.centre)
    h, w = shape
    lo = np.clip(np.floor(quad.min(axis=0)).astype(int), 0, [w - 1, h - 1])
    hi = np.clip(np.ceil(quad.max(axis=0)).astype(int), 0, [w - 1, h - 1])
    mask = np.zeros((hi[1] - lo[1] + 1, hi[0] - lo[0] + 1), dtype=np.uint8)
    cv2.fillConvexPoly(mask, np.rint(quad - lo).astype(np.int32), 1)
    rows, cols = np.nonzero(mask)
    return rows + lo[1], cols + lo[0]


def corner_pixels(read: MarkerRead, shape: tuple[int, int], limits: ReadLimits = READ_LIMITS,
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Rows and columns of the read's corners pulled ``limits.shrink`` towards its centre (inside the face)."""
    quad = read.centre + limits.shrink * (read.corners - read.centre)
    h, w = shape
    cols = np.clip(np.rint(quad[:, 0]).astype(int), 0, w - 1)
    rows = np.clip(np.rint(quad[:, 1]).astype(int), 0, h - 1)
    return rows, cols


def marker_edge(read: MarkerRead, origins: np.ndarray, directions: np.ndarray, normal: np.ndarray,
                offset: float) -> np.ndarray | None:
    """A unit edge direction of the marker in its face plane (``normal . p = offset``), or None.

    The read's corners are cast as rays (``origins``, ``directions``: one per corner) onto the
    plane fitted to the face's depth points; the mean of its four edges (two of them turned a
    quarter about the normal) is the direction. It fixes the cube's turn about a face that is
    the only one seen, which the face's depth points alone leave open.
    """
    along = directions @ normal
    if np.any(np.abs(along) < 1e-6):
        return None
    corners = origins + ((offset - origins @ normal) / along)[:, None] * directions
    first = (corners[1] - corners[0]) + (corners[2] - corners[3])
    second = np.cross(normal, (corners[3] - corners[0]) + (corners[2] - corners[1]))
    edge = first + (second if second @ first >= 0 else -second)
    edge -= (edge @ normal) * normal
    length = float(np.linalg.norm(edge))
    return edge / length if length > 1e-9 else None


def plausible(corners: np.ndarray, size: float, limits: ReadLimits = READ_LIMITS) -> bool:
    """True if four back-projected corners (:func:`corner_pixels`) span a marker printed on a cube of ``size``."""
    side = size * MARKER_LAYOUT.marker_fraction * limits.shrink
    sides = np.linalg.norm(corners - np.roll(corners, 1, axis=0), axis=1)
    return bool(np.all(np.abs(sides - side) < limits.side_tolerance * side))


__all__ = ["MarkerRead", "READ_LIMITS", "RETRY_LIMITS", "ReadLimits", "corner_pixels", "face_pixels", "marker_edge",
           "plausible", "read_markers"]
