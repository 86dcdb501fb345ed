"""RGB-D perception: what a real colour-and-depth camera could give.

Each fixed camera renders a colour image and a depth image (no segmentation ids). A cube is
known by the ArUco marker printed on its faces (:mod:`.fiducials`): the pixels round each
marker read are back-projected with depth, and a plane fitted to them is that face; the
face's normal and the marker's edge in it give the cube's frame, merged over every read of
the cube in every view (:mod:`.face_reads`). Its most upward axis gives the tilt, a side axis
the yaw, and each read face pins the centre half a cube behind it. While some cube has no read,
the images are decoded once more at another sampling of the markers' cells, then
further views (:func:`~.camera.fallback_cameras`: higher, or from behind the arm) are rendered
one at a time (not for a cube interpretation places in the hand by elimination); a cube with
no read in any view is unseen (never guessed from its colour, which is cosmetic); so is one
read in places too far apart to be one cube.
Optional Gaussian noise on depth (metres, along the optical axis) and colour (8-bit levels)
stands for a real sensor.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from csql_sim.infra.errors import CsqlError
from csql_sim.sim.perception.camera import CAMERA_TOLERANCES, Camera, capture, fallback_cameras, perception_cameras
from csql_sim.sim.perception.face_reads import FaceRead, cube_centre, cube_frame, read_view
from csql_sim.sim.perception.fiducials import RETRY_LIMITS
from csql_sim.sim.perception.poses import BlockObs, Observation, interpret, wrap_quarter
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


def estimate_cube(faces: list[FaceRead], size: float) -> BlockObs:
    """Centre, tilt and yaw of a cube from its face reads (at least one)."""
    axes = cube_frame(faces)
    centre = cube_centre(faces, axes, size)
    k = int(np.argmax(np.abs(axes[:, 2])))
    tilt = math.acos(min(1.0, abs(float(axes[k, 2]))))
    side = axes[(k + 1) % 3]
    yaw = wrap_quarter(math.atan2(float(side[1]), float(side[0])))
    frame = tuple(tuple(float(v) for v in a) for a in axes)
    return BlockObs((float(centre[0]), float(centre[1]), float(centre[2])), tilt, yaw, axes=frame, reads=len(faces))


Render = Callable[[Camera], tuple[np.ndarray, np.ndarray]]
"""A camera's colour image (h, w, 3 uint8) and depth buffer (h, w) of the scene now."""


View = tuple[Camera, np.ndarray, np.ndarray]
"""A camera and the colour image and depth buffer it gave (sensor noise added)."""


def read_faces(render: Render, cameras: tuple[Camera, ...], faces: list[list[FaceRead]], size: float,
               noise: CameraNoise, rng: np.random.Generator) -> list[View]:
    """Add each view's marker reads to ``faces`` (one list per cube); the views, for :func:`reread_faces`."""
    views = []
    for camera in cameras:
        rgb, depth = render(camera)
        if noise.active:
            rgb, depth = add_noise(rgb, depth, camera, noise, rng)
        for face in read_view(camera, rgb, depth, len(faces), size, noise.depth):
            faces[face.cube].append(face)
        views.append((camera, rgb, depth))
    return views


def reread_faces(views: list[View], faces: list[list[FaceRead]], size: float, noise: CameraNoise) -> None:
    """Decode the views' images again with :data:`~.fiducials.RETRY_LIMITS`, for the cubes with no read yet."""
    unread = {cube for cube, reads in enumerate(faces) if not reads}
    for camera, rgb, depth in views if unread else ():
        for face in read_view(camera, rgb, depth, len(faces), size, noise.depth, RETRY_LIMITS):
            if face.cube in unread:
                faces[face.cube].append(face)


def estimate_cubes(faces: list[list[FaceRead]], size: float) -> tuple[BlockObs, ...]:
    """Each cube's estimate from its face reads; one with none, or read in places apart, is unseen."""
    blocks = []
    for reads in faces:
        centres = np.array([f.centre for f in reads]).reshape(-1, 3)
        apart = len(centres) > 1 and np.ptp(centres, axis=0).max() > 1.5 * size  # one id, two places: no guess
        if not len(centres) or apart:
            blocks.append(BlockObs((0.0, 0.0, -1.0), None, 0.0, visible=False, reads=len(centres)))
        else:
            blocks.append(estimate_cube(reads, size))
    return tuple(blocks)


Explained = Callable[[tuple[BlockObs, ...]], bool]
"""Whether estimates with unread cubes need no further view (e.g. the one unread cube is in the hand)."""


def locate_cubes(render: Render, cameras: tuple[Camera, ...], n: int, size: float,
                 noise: CameraNoise = NO_NOISE, rng: np.random.Generator | None = None,
                 fallback: tuple[Camera, ...] = (), explained: Explained | None = None) -> tuple[BlockObs, ...]:
    """Every cube's estimate from the views' marker reads; a cube no view read (or read apart) is unseen.

    While some cube has no read (and ``explained`` does not hold), the images already taken are
    decoded again (:func:`reread_faces`) before a fallback view is rendered, and each fallback
    view is decoded both ways.

    Args:
        render: the colour and depth images of a camera.
        cameras: the views.
        n: cubes 0..n-1 (marker ids).
        size: their edge, m.
        noise: sensor noise to add.
        rng: draws the noise (a fixed generator when None).
        fallback: further views, rendered in turn only while some cube has no read.
        explained: when it holds for the estimates, no further view is rendered though a cube is unread.
    """
    rng = rng if rng is not None else np.random.default_rng(0)
    faces: list[list[FaceRead]] = [[] for _ in range(n)]

    def done(blocks: tuple[BlockObs, ...]) -> bool:
        return all(b.visible for b in blocks) or (explained is not None and explained(blocks))

    views = read_faces(render, cameras, faces, size, noise, rng)
    blocks = estimate_cubes(faces, size)
    if not done(blocks):
        reread_faces(views, faces, size, noise)
        blocks = estimate_cubes(faces, size)
    for camera in fallback:
        if done(blocks):
            break
        reread_faces(read_faces(render, (camera,), faces, size, noise, rng), faces, size, noise)
        blocks = estimate_cubes(faces, size)
    return blocks


def observe_rgbd(scene: Scene, panda: Panda, cameras: tuple[Camera, ...] | None = None,
                 noise: CameraNoise = NO_NOISE, rng: np.random.Generator | None = None,
                 fallback: tuple[Camera, ...] | None = None) -> Observation:
    """Camera-mode observation from colour and depth images only (plus the arm's proprioception).

    Args:
        scene: the physical scene (rendered, never read for poses).
        panda: the arm: grasp point and finger opening by proprioception.
        cameras: the fixed perception cameras (default: :func:`~csql_sim.sim.perception.camera.perception_cameras` n).
        noise: sensor noise to add.
        rng: draws the noise (a fixed generator when None).
        fallback: views rendered only while a cube is unread (default:
            :func:`~csql_sim.sim.perception.camera.fallback_cameras` n).
    """
    cameras = perception_cameras(scene.n) if cameras is None else cameras
    fallback = fallback_cameras(scene.n) if fallback is None else fallback
    size = scene.config.physics.cube_size

    grasp, width = tuple(panda.ee_position()), panda.finger_width()

    def render(camera: Camera) -> tuple[np.ndarray, np.ndarray]:
        return capture(scene, camera, camera.width, camera.height)[:2]

    def explained(blocks: tuple[BlockObs, ...]) -> bool:  # interpretation places every unread cube (in the hand)
        return not interpret(Observation(blocks, grasp, width, size), CAMERA_TOLERANCES).unseen

    blocks = locate_cubes(render, cameras, scene.n, size, noise, rng, fallback, explained)
    return Observation(blocks, grasp, width, size)


__all__ = ["CameraNoise", "NO_NOISE", "estimate_cube", "estimate_cubes", "locate_cubes", "observe_rgbd"]
