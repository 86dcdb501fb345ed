"""The physics client: one pybullet DIRECT connection behind small typed methods.

This is the only module that imports ``pybullet``. :class:`PhysicsClient` owns a client
and wraps every physics call the package makes (body creation, stepping, link and joint
states, inverse kinematics, motor targets, external forces, rendering), always passing
``physicsClientId`` explicitly. Client-free math (quaternions, camera matrices) is in
module-level functions. What the bodies *are* (table, Panda, cubes) is
:class:`csql_sim.sim.world.scene.Scene`'s business.
"""

from __future__ import annotations

import ctypes
import importlib
import os
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from types import ModuleType
from typing import Any

import numpy as np
import pybullet_data

from csql_sim.sim.world.box_mesh import box_mesh
from csql_sim.sim.world.config import PhysicsConfig


@contextmanager
def quiet_output() -> Iterator[None]:
    """Send the C-level stdout and stderr (fds 1 and 2) to /dev/null for the block.

    pybullet prints a "pybullet build time: ..." banner from C when it is imported (on
    stderr in current wheels, on stdout in older ones), and the EGL plugin prints its device
    and driver details with C ``printf``; either would pollute the CLI's output or make a
    one-line error two lines. C's stdio buffers are flushed while fds 1 and 2 still point at
    the null device, then both are restored. Where file descriptors cannot be duplicated,
    the block runs with the streams as they are.
    """
    for stream in (sys.stdout, sys.stderr):
        if stream is not None:
            stream.flush()
    try:
        saved = (os.dup(1), os.dup(2))
    except (OSError, ValueError):
        yield
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        yield
    finally:
        try:
            ctypes.CDLL(None).fflush(None)
        except (OSError, AttributeError, TypeError):
            pass
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (*saved, devnull):
            os.close(fd)


def _import_quietly(name: str) -> ModuleType:
    """Import the module ``name`` under :func:`quiet_output`."""
    with quiet_output():
        return importlib.import_module(name)


pybullet = _import_quietly("pybullet")

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]


# ---------------------------------------------------------------- client-free helpers


def quaternion_from_euler(euler: Vec3) -> Quat:
    """The quaternion (x, y, z, w) of roll, pitch and yaw angles, rad (pybullet's convention)."""
    return pybullet.getQuaternionFromEuler(euler)


def rotation_matrix(quaternion: Quat) -> np.ndarray:
    """The 3x3 rotation matrix of a quaternion (x, y, z, w)."""
    return np.array(pybullet.getMatrixFromQuaternion(quaternion)).reshape(3, 3)


def view_matrix(eye: Vec3, target: Vec3, up: Vec3) -> list[float]:
    """The view matrix of a camera at ``eye`` looking at ``target`` (column-major, 16 floats)."""
    return list(pybullet.computeViewMatrix(eye, target, up))


def projection_matrix(fov: float, aspect: float, near: float, far: float) -> list[float]:
    """The perspective projection matrix (column-major, 16 floats); ``fov`` vertical, degrees."""
    return list(pybullet.computeProjectionMatrixFOV(fov, aspect, near, far))


@dataclass(frozen=True)
class Pose:
    """Position and orientation quaternion (x, y, z, w) of a body."""

    position: Vec3
    orientation: Quat


class PhysicsClient:
    """One pybullet DIRECT client with gravity, time step and solver set from ``physics``.

    Attributes:
        client: the pybullet client id (-1 once closed).
        steps: simulation steps taken so far.
        step_wall: wall seconds spent in :meth:`step` (benchmarks only; never used for control).
    """

    def __init__(self, physics: PhysicsConfig, renderer_plugin: tuple[str, str] | None = None) -> None:
        self.client = pybullet.connect(pybullet.DIRECT)
        self.steps = 0
        self.step_wall = 0.0
        self._step_hooks: list[Callable[[Any], None]] = []
        self._plugins: list[int] = []
        self.sleeping = physics.sleep_threshold > 0  # cubes may sleep (Scene); teleports and forces wake them
        self.opengl = False  # True once an OpenGL renderer plugin (EGL) draws this client's images
        if renderer_plugin is not None:
            self._load_renderer_plugin(*renderer_plugin)
        cid = self.client
        pybullet.setAdditionalSearchPath(pybullet_data.getDataPath(), physicsClientId=cid)
        pybullet.setTimeStep(physics.time_step, physicsClientId=cid)
        pybullet.setPhysicsEngineParameter(numSolverIterations=physics.solver_iterations, physicsClientId=cid)
        pybullet.setGravity(0, 0, physics.gravity, physicsClientId=cid)

    def _load_renderer_plugin(self, path: str, name: str) -> None:
        """Load a renderer plugin (pybullet's eglRenderer) before any body exists.

        The plugin only draws shapes created after it is loaded, and then draws every
        image of this client (``render`` asks for pybullet's OpenGL renderer); so only
        replay scenes for video load it, and perception keeps the TinyRenderer.
        """
        plugin = pybullet.loadPlugin(path, name, physicsClientId=self.client)
        if plugin >= 0:
            self._plugins.append(plugin)
            self.opengl = True

    def close(self) -> None:
        """Unload plugins and disconnect the client (idempotent)."""
        if self.client >= 0:
            for plugin in self._plugins:
                pybullet.unloadPlugin(plugin, physicsClientId=self.client)
            self._plugins.clear()
            pybullet.disconnect(physicsClientId=self.client)
            self.client = -1

    def __enter__(self):  # noqa: ANN204 - returns the subclass instance
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------ creating bodies

    def add_box(self, half_extents: Vec3, mass: float, rgba: tuple[float, float, float, float],
                position: Vec3, textured: bool = False, **dynamics: float) -> int:
        """A box body (mass 0: static) at ``position``; ``dynamics`` go to changeDynamics of its base.

        ``textured``: the visual is a box mesh whose every face shows the whole of a texture set
        later (:meth:`set_texture`); pybullet's own box visual maps a texture to a few texels per face.
        """
        cid = self.client
        col = pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=half_extents, physicsClientId=cid)
        if textured:
            vertices, normals, uvs, indices = box_mesh(half_extents)
            vis = pybullet.createVisualShape(pybullet.GEOM_MESH, vertices=vertices, normals=normals, uvs=uvs,
                                             indices=indices, rgbaColor=rgba, physicsClientId=cid)
        else:
            vis = pybullet.createVisualShape(pybullet.GEOM_BOX, halfExtents=half_extents, rgbaColor=rgba,
                                             physicsClientId=cid)
        body = pybullet.createMultiBody(mass, col, vis, basePosition=position, physicsClientId=cid)
        pybullet.changeDynamics(body, -1, **dynamics, physicsClientId=cid)
        return body

    def load_texture(self, path: str) -> int:
        """The texture id of an image file (PNG), loaded into this client."""
        return pybullet.loadTexture(path, physicsClientId=self.client)

    def set_texture(self, body: int, texture: int) -> None:
        """Show ``texture`` on the base visual of ``body`` (a :meth:`add_box` with ``textured``)."""
        pybullet.changeVisualShape(body, -1, textureUniqueId=texture, physicsClientId=self.client)

    def load_fixed_urdf(self, path: str) -> int:
        """A fixed-base articulated body from pybullet_data, self-collision excluding parents."""
        return pybullet.loadURDF(path, basePosition=(0.0, 0.0, 0.0), useFixedBase=True,
                                 flags=pybullet.URDF_USE_SELF_COLLISION_EXCLUDE_PARENT, physicsClientId=self.client)

    def set_link_dynamics(self, body: int, link: int, **dynamics: float) -> None:
        """ChangeDynamics of one link (frictions)."""
        pybullet.changeDynamics(body, link, **dynamics, physicsClientId=self.client)

    def add_gear(self, body: int, link_a: int, link_b: int, ratio: float, erp: float, max_force: float) -> None:
        """A gear constraint between two links of one body (a robot's own coupling)."""
        cid = self.client
        gear = pybullet.createConstraint(body, link_a, body, link_b, pybullet.JOINT_GEAR, (1, 0, 0), (0, 0, 0),
                                         (0, 0, 0), physicsClientId=cid)
        pybullet.changeConstraint(gear, gearRatio=ratio, erp=erp, maxForce=max_force, physicsClientId=cid)

    # ------------------------------------------------------------ stepping

    def add_step_hook(self, hook: Callable[[Any], None]) -> None:
        """Call ``hook(self)`` after every simulation step (e.g. a pose recorder)."""
        self._step_hooks.append(hook)

    def step(self, count: int = 1) -> None:
        """Advance the physics by ``count`` steps."""
        cid = self.client
        hooks = self._step_hooks
        t = time.perf_counter()
        for _ in range(count):
            pybullet.stepSimulation(physicsClientId=cid)
            self.steps += 1
            for hook in hooks:
                hook(self)
        self.step_wall += time.perf_counter() - t

    # ------------------------------------------------------------ bodies

    def body_pose(self, body: int) -> Pose:
        """The base pose of ``body``."""
        pos, orn = pybullet.getBasePositionAndOrientation(body, physicsClientId=self.client)
        return Pose(tuple(pos), tuple(orn))

    def body_speed(self, body: int) -> tuple[float, float]:
        """Linear (m/s) and angular (rad/s) speed of ``body``'s base."""
        lin, ang = pybullet.getBaseVelocity(body, physicsClientId=self.client)
        return float(np.linalg.norm(lin)), float(np.linalg.norm(ang))

    def set_body_pose(self, body: int, position: Vec3, orientation: Quat) -> None:
        """Teleport ``body`` (scene construction, replay and tests; never during an episode); it wakes."""
        pybullet.resetBasePositionAndOrientation(body, position, orientation, physicsClientId=self.client)
        self.wake(body)

    def allow_sleep(self, body: int, threshold: float) -> None:
        """Let Bullet put ``body`` to sleep after 2 s with its motion below ``threshold``.

        The motion is Bullet's: squared linear (m/s) plus angular (rad/s) speed. Bullet wakes the
        body when an awake one (the arm, a moving cube) touches it or what it rests on.
        """
        pybullet.changeDynamics(body, -1, activationState=pybullet.ACTIVATION_STATE_ENABLE_SLEEPING,
                                sleepThreshold=threshold, physicsClientId=self.client)

    def wake(self, body: int) -> None:
        """Wake ``body`` if it may sleep (:meth:`allow_sleep`); nothing else changes."""
        if self.sleeping:
            pybullet.changeDynamics(body, -1, activationState=pybullet.ACTIVATION_STATE_WAKE_UP,
                                    physicsClientId=self.client)

    def stop_body(self, body: int) -> None:
        """Zero ``body``'s linear and angular velocity (scene construction only)."""
        pybullet.resetBaseVelocity(body, (0, 0, 0), (0, 0, 0), physicsClientId=self.client)

    def contact_bodies(self, body: int, link: int | None = None) -> set[int]:
        """Ids of bodies touching ``body`` (optionally only its link ``link``)."""
        kwargs = {} if link is None else {"linkIndexA": link}
        pts = pybullet.getContactPoints(bodyA=body, physicsClientId=self.client, **kwargs)
        return {p[2] for p in pts}

    def body_count(self) -> int:
        """Number of bodies in the world."""
        return pybullet.getNumBodies(physicsClientId=self.client)

    def constraint_bodies(self) -> list[tuple[int, int]]:
        """(parent body, child body) of every constraint in the world."""
        cid = self.client
        pairs = []
        for k in range(pybullet.getNumConstraints(physicsClientId=cid)):
            info = pybullet.getConstraintInfo(pybullet.getConstraintUniqueId(k, physicsClientId=cid),
                                              physicsClientId=cid)
            pairs.append((info[0], info[2]))
        return pairs

    # ------------------------------------------------------------ links and joints

    def link_state(self, body: int, link: int, velocity: bool = False) -> tuple[Vec3, Quat, Vec3 | None]:
        """World position and orientation of a link's URDF frame, and its linear velocity (m/s).

        Forward kinematics is recomputed; the velocity is computed (and returned) only
        when ``velocity`` is True, otherwise it is None.
        """
        if velocity:
            st = pybullet.getLinkState(body, link, computeLinkVelocity=True, computeForwardKinematics=True,
                                       physicsClientId=self.client)
            return st[4], st[5], st[6]
        st = pybullet.getLinkState(body, link, computeForwardKinematics=True, physicsClientId=self.client)
        return st[4], st[5], None

    def mass_frames(self, body: int, links: Sequence[int]) -> list[Pose]:
        """World poses of links' centre-of-mass frames (-1: the base), forward kinematics recomputed."""
        cid = self.client
        out = []
        for link in links:
            if link < 0:
                pos, orn = pybullet.getBasePositionAndOrientation(body, physicsClientId=cid)
            else:
                pos, orn = pybullet.getLinkState(body, link, computeForwardKinematics=True, physicsClientId=cid)[:2]
            out.append(Pose(tuple(pos), tuple(orn)))
        return out

    def mesh_shapes(self, body: int, link: int) -> list[tuple[str, Vec3, Pose]]:
        """A link's collision meshes: (file, scale, pose in the link's centre-of-mass frame) each."""
        shapes = pybullet.getCollisionShapeData(body, link, physicsClientId=self.client)
        return [(s[4].decode() if isinstance(s[4], bytes) else s[4], tuple(s[3]), Pose(tuple(s[5]), tuple(s[6])))
                for s in shapes if s[2] == pybullet.GEOM_MESH]

    def joint_positions(self, body: int, joints: Sequence[int]) -> list[float]:
        """Current positions of the given joints, in order (rad or m)."""
        cid = self.client
        return [pybullet.getJointState(body, j, physicsClientId=cid)[0] for j in joints]

    def reset_joint(self, body: int, joint: int, position: float) -> None:
        """Set a joint's position outright (scene construction and replay only)."""
        pybullet.resetJointState(body, joint, position, physicsClientId=self.client)

    def inverse_kinematics(self, body: int, link: int, position: Vec3, orientation: Quat,
                           lower: Sequence[float], upper: Sequence[float], ranges: Sequence[float],
                           rest: Sequence[float], iterations: int, threshold: float) -> list[float]:
        """Joint positions (every movable joint) placing ``link`` at ``position`` with ``orientation``.

        Args:
            body: the articulated body.
            link: the link to place.
            position: its target world position, m.
            orientation: its target world orientation (x, y, z, w).
            lower: lower joint limits of the null space.
            upper: upper joint limits of the null space.
            ranges: joint ranges of the null space.
            rest: rest pose the null space pulls towards.
            iterations: most IK iterations.
            threshold: residual at which the iteration stops.
        """
        q = pybullet.calculateInverseKinematics(
            body, link, position, orientation,
            lowerLimits=lower, upperLimits=upper, jointRanges=ranges, restPoses=rest,
            maxNumIterations=iterations, residualThreshold=threshold,
            physicsClientId=self.client)
        return list(q)

    def set_joint_targets(self, body: int, joints: Sequence[int], targets: Sequence[float],
                          forces: Sequence[float], max_velocity: float, position_gain: float | None = None,
                          ) -> None:
        """Position-control motors: drive each joint towards its target with at most its force.

        Args:
            body: the articulated body.
            joints: joint indices.
            targets: target position of each joint.
            forces: most force (or torque) of each joint's motor.
            max_velocity: speed cap of every joint.
            position_gain: the motors' position gain (pybullet's default when None).
        """
        cid = self.client
        gain = {} if position_gain is None else {"positionGain": position_gain}
        for j, target, force in zip(joints, targets, forces, strict=True):
            pybullet.setJointMotorControl2(
                body, j, pybullet.POSITION_CONTROL, targetPosition=target, force=force,
                maxVelocity=max_velocity, **gain, physicsClientId=cid)

    def apply_force(self, body: int, force: Vec3, position: Vec3) -> None:
        """Apply ``force`` (N, world frame) at ``position`` (world) to the base of ``body`` for the next step."""
        self.wake(body)
        pybullet.applyExternalForce(body, -1, force, position, pybullet.WORLD_FRAME, physicsClientId=self.client)

    # ------------------------------------------------------------ rendering

    def render(self, view: Sequence[float], projection: Sequence[float], width: int, height: int,
               segmentation: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """RGB (h, w, 3 uint8), depth buffer (h, w) and segmentation ids (h, w).

        Drawn by the TinyRenderer, or by the OpenGL plugin where one is loaded. The
        segmentation mask is only computed when ``segmentation`` is True.
        """
        flags = 0 if segmentation else pybullet.ER_NO_SEGMENTATION_MASK
        renderer = pybullet.ER_BULLET_HARDWARE_OPENGL if self.opengl else pybullet.ER_TINY_RENDERER
        _, _, rgba, depth, seg = pybullet.getCameraImage(
            width, height, view, projection, renderer=renderer, flags=flags, physicsClientId=self.client)
        rgb = np.asarray(rgba, dtype=np.uint8).reshape(height, width, 4)[:, :, :3]
        return (rgb, np.asarray(depth, dtype=np.float64).reshape(height, width),
                np.asarray(seg).reshape(height, width))


__all__ = [
    "PhysicsClient",
    "Pose",
    "Quat",
    "Vec3",
    "projection_matrix",
    "quaternion_from_euler",
    "rotation_matrix",
    "view_matrix",
]
