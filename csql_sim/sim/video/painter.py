"""The flat painter: a fast CPU drawing of a replay scene from recorded poses (``--renderer flat``).

pybullet's renderers draw the Panda's full meshes: on one CPU core the TinyRenderer takes
about 0.45 s a 640x480 frame, and the EGL plugin on Mesa's software rasteriser about the
same, so a video of a long episode took minutes. The painter draws what a video needs in a
few milliseconds, with Pillow:

* the table and the cubes as boxes: their faces that look towards the camera, shaded by
  the angle of a fixed light (flat shading), with darker edges;
* each Panda link as the silhouette of its collision mesh: the 2-D convex hull of the
  projected support points of the mesh (:class:`ArmShape`), at the link pose recorded
  with the frame;

far things first (the painter's algorithm, one depth per cube or link). Frames depend only
on the recorded poses, the camera and the frame size: they are the same whichever process
paints them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache

import numpy as np
from PIL import Image, ImageDraw

from csql_sim.sim.perception.camera import Camera
from csql_sim.sim.video.replay import PANDA_JOINTS
from csql_sim.sim.world.config import SimConfig, cube_colour
from csql_sim.sim.world.scene import Pose, Scene, rotation_matrix

LIGHT = np.array([0.45, 0.3, 1.0]) / np.linalg.norm([0.45, 0.3, 1.0])
AMBIENT, DIFFUSE = 0.5, 0.5
SKY, FLOOR = (205, 214, 226), (238, 240, 243)  # background: top and bottom of the gradient
TABLE_RGB = (184, 153, 115)
ARM_RGB, HAND_RGB, ARM_EDGE = (240, 240, 240), (150, 150, 155), (105, 105, 110)
SUPPORT_DIRECTIONS = 80  # support points kept per link mesh (its silhouette's outline)
_SIGNS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
_FACES = ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3))
_NORMALS = np.array([[-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1]], dtype=float)


@dataclass(frozen=True)
class Projection:
    """A camera's projection onto a ``width`` x ``height`` image: pixel coordinates and depth."""

    matrix: np.ndarray  # projection @ view, 4x4
    eye: np.ndarray
    width: int
    height: int
    near: float
    focal: float  # pixels per metre at a depth of 1 m

    @classmethod
    def of(cls, camera: Camera, width: int, height: int) -> Projection:
        view, proj = camera.matrices(width, height)
        m = np.asarray(proj).reshape(4, 4, order="F") @ np.asarray(view).reshape(4, 4, order="F")
        focal = height / (2.0 * np.tan(np.radians(camera.fov) / 2))
        return cls(m, np.asarray(camera.eye, dtype=float), width, height, camera.near, float(focal))

    def __call__(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pixel coordinates (k, 2) and depths along the view axis (k,) of world points (k, 3)."""
        clip = points @ self.matrix[:, :3].T + self.matrix[:, 3]
        w = clip[:, 3]
        safe = np.where(w > 1e-9, w, 1e-9)
        xy = np.empty((len(points), 2))
        xy[:, 0] = (clip[:, 0] / safe + 1.0) * 0.5 * self.width
        xy[:, 1] = (1.0 - clip[:, 1] / safe) * 0.5 * self.height
        return xy, w


def _support_points(points: np.ndarray, k: int = SUPPORT_DIRECTIONS) -> np.ndarray:
    """The points of ``points`` furthest along ``k`` directions spread over the sphere (unique)."""
    i = np.arange(k) + 0.5
    phi, theta = np.arccos(1 - 2 * i / k), np.pi * (1 + 5 ** 0.5) * i
    dirs = np.stack([np.cos(theta) * np.sin(phi), np.sin(theta) * np.sin(phi), np.cos(phi)], axis=1)
    return points[np.unique(np.argmax(points @ dirs.T, axis=0))]


@cache
def _obj_vertices(path: str) -> np.ndarray:
    with open(path, encoding="utf-8", errors="replace") as fh:
        rows = [line.split()[1:4] for line in fh if line.startswith("v ")]
    return np.asarray(rows, dtype=float)


def _transform(pose: Pose, points: np.ndarray) -> np.ndarray:
    return points @ rotation_matrix(pose.orientation).T + np.asarray(pose.position)


@dataclass(frozen=True)
class ArmShape:
    """The Panda's links as support points of their collision meshes, in each link's centre-of-mass frame.

    Made once from a scene (:meth:`of`); a recording keeps it with each frame's link poses,
    so painting needs no physics client.
    """

    links: tuple[int, ...]
    points: tuple[np.ndarray, ...]

    @classmethod
    def of(cls, scene: Scene) -> ArmShape:
        """The shape of ``scene``'s Panda."""
        body = scene.bodies["panda"]
        links, points = [], []
        for link in range(-1, len(PANDA_JOINTS)):
            parts = [_transform(pose, _obj_vertices(path) * np.asarray(scale))
                     for path, scale, pose in scene.mesh_shapes(body, link)]
            if parts:
                links.append(link)
                points.append(_support_points(np.concatenate(parts)))
        return cls(tuple(links), tuple(points))

    def poses(self, scene: Scene) -> tuple[Pose, ...]:
        """The world poses of the links' centre-of-mass frames in ``scene`` now (what a frame records)."""
        return tuple(scene.mass_frames(scene.bodies["panda"], self.links))

    def posed(self, frames: Sequence[Pose]) -> list[np.ndarray]:
        """World support points of every link, its centre-of-mass frame at ``frames``."""
        return [_transform(pose, pts) for pose, pts in zip(frames, self.points, strict=True)]


_OUTLINE = np.stack([np.cos(np.linspace(0, 2 * np.pi, 48, endpoint=False)),
                     np.sin(np.linspace(0, 2 * np.pi, 48, endpoint=False))])


def _outline(xy: np.ndarray) -> list[tuple[float, float]]:
    """A convex polygon through the points of ``xy`` furthest along 48 directions, in turn.

    The 2-D convex hull's vertices that bound it in those directions: at a link's size on the
    screen it is the hull to within a pixel.
    """
    extreme = np.argmax(xy @ _OUTLINE, axis=0)
    keep = np.concatenate(([True], extreme[1:] != extreme[:-1]))
    return [tuple(p) for p in xy[extreme[keep]].tolist()]


@cache
def _background(width: int, height: int) -> Image.Image:
    t = np.linspace(0.0, 1.0, height)[:, None]
    rows = (1 - t) * np.asarray(SKY) + t * np.asarray(FLOOR)
    return Image.fromarray(np.repeat(rows[:, None, :], width, axis=1).astype(np.uint8))


class Painter:
    """Paints frames of one scene kind: ``n`` cubes, the table of ``config``, the Panda of ``arm`` (None: none)."""

    def __init__(self, n: int, config: SimConfig, arm: ArmShape | None = None) -> None:
        self.arm = arm
        pc = config.physics
        self.cube_half = np.full(3, pc.cube_size / 2)
        self.table = (np.asarray(pc.table_half_extents), np.asarray(pc.table_centre))
        self.cube_rgb = [tuple(int(255 * c) for c in cube_colour(i)[:3]) for i in range(n)]
        self._grounds: dict[tuple[bytes, int, int], Image.Image] = {}

    def paint(self, poses: tuple[Pose, ...], links: Sequence[Pose] | None, proj: Projection) -> Image.Image:
        """The picture of the cubes at ``poses`` and the Panda's links at ``links`` (None: no arm, as in a map)."""
        img = self._ground(proj).copy()
        draw = ImageDraw.Draw(img)
        n = len(poses)
        centres = np.asarray([p.position for p in poses], dtype=float).reshape(n, 3)
        rots = np.asarray([rotation_matrix(p.orientation) for p in poses]).reshape(n, 3, 3)
        cube_depth = proj(centres)[1] if n else np.zeros(0)
        links = self.arm.posed(links) if links and self.arm is not None else []
        sizes = [len(p) for p in links]
        link_xy, link_depth = proj(np.concatenate(links)) if links else (np.zeros((0, 2)), np.zeros(0))
        bounds = np.cumsum([0, *sizes])
        order = [(float(cube_depth[i]), 0, i) for i in range(n)]
        order += [(float(link_depth[bounds[k]:bounds[k + 1]].mean()), 1, k) for k in range(len(links))]
        cubes = None
        for _, kind, i in sorted(order, key=lambda item: (-item[0], item[1], item[2])):
            if kind == 0:
                if cubes is None:
                    cubes = self._cube_faces(proj, centres, rots)
                self._draw_faces(draw, cubes, i)
            elif (link_depth[bounds[i]:bounds[i + 1]] > proj.near).all():
                hand = self.arm.links[i] >= 8
                draw.polygon(_outline(link_xy[bounds[i]:bounds[i + 1]]), fill=HAND_RGB if hand else ARM_RGB,
                             outline=ARM_EDGE)
        return img

    def _ground(self, proj: Projection) -> Image.Image:
        """The background and the table (nothing is ever behind them), drawn once per view."""
        key = (proj.matrix.tobytes(), proj.width, proj.height)
        if key not in self._grounds:
            img = _background(proj.width, proj.height).copy()
            half, centre = self.table
            self._boxes(ImageDraw.Draw(img), proj, centre[None], np.eye(3)[None], half, [TABLE_RGB], [0])
            self._grounds[key] = img
        return self._grounds[key]

    def _cube_faces(self, proj: Projection, centres: np.ndarray, rots: np.ndarray) -> list:
        return self._faces(proj, centres, rots, self.cube_half, self.cube_rgb)

    @staticmethod
    def _faces(proj: Projection, centres: np.ndarray, rots: np.ndarray, half: np.ndarray,
               colours: list[tuple[int, int, int]]) -> list[list[tuple[list, tuple, tuple]]]:
        """For each box, its faces towards the camera: (polygon, fill, edge colour); [] when behind the camera."""
        k = len(centres)
        corners = centres[:, None, :] + np.einsum("cj,bij->bci", _SIGNS * half, rots)  # (k, 8, 3)
        xy, depth = proj(corners.reshape(-1, 3))
        xy, depth = xy.reshape(k, 8, 2), depth.reshape(k, 8)
        normals = np.einsum("fj,bij->bfi", _NORMALS, rots)  # (k, 6, 3)
        mids = centres[:, None, :] + np.einsum("fj,bij->bfi", _NORMALS * half, rots)
        facing = np.einsum("bfi,bfi->bf", normals, proj.eye - mids) > 0
        light = AMBIENT + DIFFUSE * np.maximum(0.0, normals @ LIGHT)  # (k, 6)
        out = []
        for b in range(k):
            if (depth[b] <= proj.near).any():
                out.append([])
                continue
            rgb, pts = colours[b], xy[b].tolist()
            edge = tuple(int(c * 0.55) for c in rgb)
            out.append([([tuple(pts[c]) for c in _FACES[f]], tuple(min(255, int(c * light[b, f])) for c in rgb), edge)
                        for f in np.flatnonzero(facing[b])])
        return out

    @staticmethod
    def _draw_faces(draw: ImageDraw.ImageDraw, faces: list, i: int) -> None:
        for polygon, fill, edge in faces[i]:
            draw.polygon(polygon, fill=fill, outline=edge)

    def _boxes(self, draw: ImageDraw.ImageDraw, proj: Projection, centres: np.ndarray, rots: np.ndarray,
               half: np.ndarray, colours: list[tuple[int, int, int]], which: list[int]) -> None:
        faces = self._faces(proj, centres, rots, half, colours)
        for i in which:
            self._draw_faces(draw, faces, i)


__all__ = ["ArmShape", "Painter", "Projection"]
