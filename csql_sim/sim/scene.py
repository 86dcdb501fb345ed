"""The physical scene: one pybullet DIRECT client, a table, a Franka Panda and n cubes.

This is the only module that imports ``pybullet``. :class:`Scene` owns a client and
wraps every physics call the package makes in a small typed method (link and joint
states, inverse kinematics, motor targets, external forces, rendering), always passing
``physicsClientId`` explicitly; client-free math (quaternions, camera matrices) is in
module-level functions. Bodies are looked up by name in :attr:`Scene.bodies`
(``"table"``, ``"panda"``, ``"A"``, ``"B"``, ...).
"""

from __future__ import annotations

import ctypes
import importlib
import os
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from types import ModuleType

import numpy as np
import pybullet_data

from csql_sim.sim.config import COLOURS, DEFAULT_CONFIG, SimConfig
from csql_sim.world import BLOCK_NAMES, State, check_n


def _import_quietly(name: str) -> ModuleType:
    """Import the module ``name`` with the C-level stdout (fd 1) sent to stderr.

    pybullet's extension prints a "pybullet build time: ..." banner with C ``printf``
    when it is imported, which would pollute the CLI's stdout. The banner is flushed
    out of C's stdio buffer while fd 1 still points at stderr, then fd 1 is restored.
    Where file descriptors cannot be duplicated, the module is imported plainly (and
    where C's buffer cannot be flushed via ctypes, the banner may still reach stdout).
    """
    try:
        if sys.stdout is not None:
            sys.stdout.flush()
        saved = os.dup(1)
    except (OSError, ValueError):
        return importlib.import_module(name)
    try:
        os.dup2(2, 1)
        return importlib.import_module(name)
    finally:
        try:
            ctypes.CDLL(None).fflush(None)
        except (OSError, AttributeError, TypeError):
            pass
        os.dup2(saved, 1)
        os.close(saved)


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


class Scene:
    """A pybullet world with its own DIRECT client.

    Args:
        n: number of cubes.
        config: geometry, physics and control settings.
        physics: False builds a replay-only scene for rendering (bodies, no stepping).
    """

    def __init__(self, n: int, config: SimConfig = DEFAULT_CONFIG, physics: bool = True) -> None:
        self.n = check_n(n)
        self.config = config
        self.client = pybullet.connect(pybullet.DIRECT)
        self.steps = 0
        self.step_wall = 0.0  # wall seconds spent in step() (benchmarks only; never used for control)
        self._step_hooks: list[Callable[[Scene], None]] = []
        self._physics = physics
        pc = self.config.physics
        cid = self.client
        pybullet.setAdditionalSearchPath(pybullet_data.getDataPath(), physicsClientId=cid)
        pybullet.setTimeStep(pc.time_step, physicsClientId=cid)
        pybullet.setPhysicsEngineParameter(numSolverIterations=pc.solver_iterations, physicsClientId=cid)
        pybullet.setGravity(0, 0, pc.gravity, physicsClientId=cid)
        self.bodies: dict[str, int] = {}
        self._load_table()
        self._load_panda()
        for i in range(n):
            self._load_cube(BLOCK_NAMES[i], COLOURS[i])

    # ------------------------------------------------------------ construction

    def _load_table(self) -> None:
        pc = self.config.physics
        cid = self.client
        col = pybullet.createCollisionShape(
            pybullet.GEOM_BOX, halfExtents=pc.table_half_extents, physicsClientId=cid)
        vis = pybullet.createVisualShape(
            pybullet.GEOM_BOX, halfExtents=pc.table_half_extents, rgbaColor=(0.72, 0.6, 0.45, 1.0),
            physicsClientId=cid)
        body = pybullet.createMultiBody(0.0, col, vis, basePosition=pc.table_centre, physicsClientId=cid)
        pybullet.changeDynamics(body, -1, lateralFriction=pc.table_friction, physicsClientId=cid)
        self.bodies["table"] = body

    def _load_panda(self) -> None:
        cid = self.client
        body = pybullet.loadURDF(
            "franka_panda/panda.urdf", basePosition=(0.0, 0.0, 0.0), useFixedBase=True,
            flags=pybullet.URDF_USE_SELF_COLLISION_EXCLUDE_PARENT, physicsClientId=cid)
        self.bodies["panda"] = body
        for link in (9, 10):
            pybullet.changeDynamics(body, link, lateralFriction=self.config.physics.finger_friction,
                                    spinningFriction=self.config.physics.finger_spinning_friction,
                                    physicsClientId=cid)
        # couple the two fingers so that they stay symmetric about the hand's axis
        gear = pybullet.createConstraint(body, 9, body, 10, pybullet.JOINT_GEAR, (1, 0, 0), (0, 0, 0), (0, 0, 0),
                                         physicsClientId=cid)
        pybullet.changeConstraint(gear, gearRatio=-1, erp=0.1, maxForce=50, physicsClientId=cid)
        for j, q in enumerate(self.config.control.home_joints):
            pybullet.resetJointState(body, j, q, physicsClientId=cid)
        for j in (9, 10):
            pybullet.resetJointState(body, j, self.config.control.finger_open, physicsClientId=cid)

    def _load_cube(self, name: str, rgba: tuple[float, float, float, float]) -> None:
        pc = self.config.physics
        cid = self.client
        half = (pc.cube_size / 2,) * 3
        col = pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=half, physicsClientId=cid)
        vis = pybullet.createVisualShape(pybullet.GEOM_BOX, halfExtents=half, rgbaColor=rgba,
                                         physicsClientId=cid)
        body = pybullet.createMultiBody(pc.cube_mass, col, vis, basePosition=(0.0, 0.0, -1.0),
                                        physicsClientId=cid)
        pybullet.changeDynamics(body, -1, lateralFriction=pc.cube_friction,
                                spinningFriction=pc.cube_spinning_friction, rollingFriction=0.0,
                                physicsClientId=cid)
        self.bodies[name] = body

    def close(self) -> None:
        """Disconnect the client (idempotent)."""
        if self.client >= 0:
            pybullet.disconnect(physicsClientId=self.client)
            self.client = -1

    def __enter__(self) -> Scene:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------ stepping

    @property
    def sim_time(self) -> float:
        """Simulated seconds since the scene was built."""
        return self.steps * self.config.physics.time_step

    def add_step_hook(self, hook: Callable[[Scene], None]) -> None:
        """Call ``hook(scene)`` after every simulation step (e.g. a pose recorder)."""
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

    def block_body(self, i: int) -> int:
        """The body id of block ``i``."""
        return self.bodies[BLOCK_NAMES[i]]

    def pose(self, name: str) -> Pose:
        """The base pose of the named body."""
        pos, orn = pybullet.getBasePositionAndOrientation(self.bodies[name], physicsClientId=self.client)
        return Pose(tuple(pos), tuple(orn))

    def block_pose(self, i: int) -> Pose:
        """The pose of block ``i``."""
        return self.pose(BLOCK_NAMES[i])

    def block_speed(self, i: int) -> tuple[float, float]:
        """Linear (m/s) and angular (rad/s) speed of block ``i``."""
        lin, ang = pybullet.getBaseVelocity(self.block_body(i), physicsClientId=self.client)
        return float(np.linalg.norm(lin)), float(np.linalg.norm(ang))

    def contact_bodies(self, body: int, link: int | None = None) -> set[int]:
        """Ids of bodies touching ``body`` (optionally only its link ``link``)."""
        kwargs = {} if link is None else {"linkIndexA": link}
        pts = pybullet.getContactPoints(bodyA=body, physicsClientId=self.client, **kwargs)
        return {p[2] for p in pts}

    def set_block_pose(self, i: int, position: Vec3, orientation: Quat) -> None:
        """Teleport block ``i`` (scene construction, replay and tests; never during an episode)."""
        pybullet.resetBasePositionAndOrientation(self.block_body(i), position, orientation,
                                                 physicsClientId=self.client)

    def body_count(self) -> int:
        """Number of bodies in the world (table, Panda and cubes)."""
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

    def joint_positions(self, body: int, joints: Sequence[int]) -> list[float]:
        """Current positions of the given joints, in order (rad or m)."""
        cid = self.client
        return [pybullet.getJointState(body, j, physicsClientId=cid)[0] for j in joints]

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
        pybullet.applyExternalForce(body, -1, force, position, pybullet.WORLD_FRAME, physicsClientId=self.client)

    # ------------------------------------------------------------ rendering

    def render(self, view: Sequence[float], projection: Sequence[float], width: int, height: int,
               segmentation: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """RGB (h, w, 3 uint8), depth buffer (h, w) and segmentation ids (h, w) from the TinyRenderer.

        The segmentation mask is only computed when ``segmentation`` is True.
        """
        flags = 0 if segmentation else pybullet.ER_NO_SEGMENTATION_MASK
        _, _, rgba, depth, seg = pybullet.getCameraImage(
            width, height, view, projection, renderer=pybullet.ER_TINY_RENDERER, flags=flags,
            physicsClientId=self.client)
        rgb = np.asarray(rgba, dtype=np.uint8).reshape(height, width, 4)[:, :, :3]
        return (rgb, np.asarray(depth, dtype=np.float64).reshape(height, width),
                np.asarray(seg).reshape(height, width))

    # ------------------------------------------------------------ layout

    def tower_slot(self, k: int, count: int) -> tuple[float, float]:
        """The xy of the k-th of ``count`` start towers."""
        lay = self.config.layout
        return lay.tower_x, (k - (count - 1) / 2) * lay.tower_spacing

    def place_towers(self, state: State, rng: np.random.Generator | None = None, jitter: bool = False) -> None:
        """Build the hand-empty part of ``state`` by placing cubes (scene construction only).

        A held block is left aside on the table at a free spot; the caller grasps it.

        Args:
            state: the configuration to build.
            rng: the generator for jitter and for the held block's spot.
            jitter: offset every cube by up to LayoutConfig.jitter_xy / jitter_yaw.
        """
        lay = self.config.layout
        size = self.config.physics.cube_size
        towers = list(state.towers())
        held = state.held
        slots = len(towers) + (1 if held is not None else 0)
        placed: list[tuple[int, float, float, float, float]] = []
        for k, tower in enumerate(towers):
            x, y = self.tower_slot(k, slots)
            for level, block in enumerate(tower):
                dx = dy = yaw = 0.0
                if jitter and rng is not None:
                    dx, dy = rng.uniform(-lay.jitter_xy, lay.jitter_xy, size=2)
                    yaw = rng.uniform(-lay.jitter_yaw, lay.jitter_yaw)
                placed.append((block, x + dx, y + dy, size / 2 + level * size + 1e-4, yaw))
        if held is not None:
            x, y = self.tower_slot(slots - 1, slots)
            placed.append((held, x, y, size / 2 + 1e-4, 0.0))
        cid = self.client
        for block, x, y, z, yaw in placed:
            orn = quaternion_from_euler((0.0, 0.0, yaw))
            self.set_block_pose(block, (x, y, z), orn)
            pybullet.resetBaseVelocity(self.block_body(block), (0, 0, 0), (0, 0, 0), physicsClientId=cid)

    # ------------------------------------------------------------ snapshot for replay

    def snapshot(self) -> tuple[tuple[Pose, ...], tuple[float, ...]]:
        """Every cube's pose and every Panda joint position (for recording)."""
        poses = tuple(self.block_pose(i) for i in range(self.n))
        joints = tuple(self.joint_positions(self.bodies["panda"], range(11)))
        return poses, joints

    def apply_snapshot(self, poses: tuple[Pose, ...], joints: tuple[float, ...]) -> None:
        """Set a recorded snapshot (replay-only scenes, never during a physics episode)."""
        if self._physics:
            raise RuntimeError("apply_snapshot is for replay scenes only")
        cid = self.client
        for i, pose in enumerate(poses):
            self.set_block_pose(i, pose.position, pose.orientation)
        panda = self.bodies["panda"]
        for j, q in enumerate(joints):
            pybullet.resetJointState(panda, j, q, physicsClientId=cid)


__all__ = [
    "Pose",
    "Quat",
    "Scene",
    "Vec3",
    "projection_matrix",
    "quaternion_from_euler",
    "rotation_matrix",
    "view_matrix",
]
