"""Perception: from block poses (or a camera) to the symbolic state and its message.

One small predicate per relation, each with named tolerances in :class:`Tolerances`.
Both perception modes produce an :class:`Observation` (estimated cube centres and the
gripper's proprioception); :func:`interpret` turns it into a :class:`~csql_sim.core.state.world.State`
(n <= 6) or a :class:`~csql_sim.core.state.state.State` (7..30 cubes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csql_sim.core.state.message import format_state_message
from csql_sim.core.state.world import HAND, TABLE, WorldError
from csql_sim.sim.world.arm_state import ArmState, Messages, arm_state, letter
from csql_sim.sim.world.robot import Panda
from csql_sim.sim.world.scene import Scene, rotation_matrix


@dataclass(frozen=True)
class Tolerances:
    """Named tolerances of the perception predicates (metres, radians, per second)."""

    stack_z: float = 0.010  # |z(x) - z(y) - size| allowed for on(x, y)
    stack_xy: float = 0.022  # horizontal offset allowed for on(x, y)
    table_z: float = 0.010  # |z(x) - size/2| allowed for on-table(x)
    tilt: float = 0.1  # rad away from lying flat on a face
    hold_dist: float = 0.025  # cube centre to grasp point for holding(x)
    hold_width: float = 0.010  # finger opening beyond the cube size still counted as gripping
    hold_search: float = 0.08  # a partly hidden cube this near closed fingers is the held one
    off_table_z: float = -0.03  # a cube centre below this has fallen off the table
    settle_linear: float = 0.01  # m/s: a slower cube counts as settled
    settle_angular: float = 0.15  # rad/s


TOLERANCES = Tolerances()


@dataclass(frozen=True)
class BlockObs:
    """What perception knows about one cube.

    Attributes:
        position: estimated centre, m.
        tilt: angle between the nearest face normal and the vertical (None if unknown).
        yaw: rotation about the vertical, modulo 90 degrees, rad.
        visible: False if the camera saw none of it.
        axes: the cube's three face normals (world frame, rows), or None if unknown.
        reads: camera mode: the marker reads that placed it (0: unseen); pose mode: 0.
    """

    position: tuple[float, float, float]
    tilt: float | None
    yaw: float
    visible: bool = True
    axes: tuple[tuple[float, float, float], ...] | None = None
    reads: int = 0


@dataclass(frozen=True)
class Observation:
    """Cubes plus the gripper's proprioception."""

    blocks: tuple[BlockObs, ...]
    grasp_point: tuple[float, float, float]
    finger_width: float
    size: float


@dataclass(frozen=True)
class Perceived:
    """The result of interpreting an observation: a state, or the reason there is none."""

    state: ArmState | None
    reason: str = ""
    stray: int | None = None  # a visible cube, not held, that rests flat nowhere (recovery can fix it)
    unseen: tuple[int, ...] = ()  # cubes no camera read: perception reports no state rather than guess theirs


def tilt_and_yaw(orientation: tuple[float, float, float, float]) -> tuple[float, float]:
    """Tilt from lying on a face, and yaw modulo 90 degrees, of a cube's orientation."""
    rot = rotation_matrix(orientation)
    k = int(np.argmax(np.abs(rot[2, :])))
    tilt = math.acos(min(1.0, abs(rot[2, k])))
    other = (k + 1) % 3
    yaw = math.atan2(rot[1, other], rot[0, other])
    return tilt, wrap_quarter(yaw)


def wrap_quarter(yaw: float) -> float:
    """Map an angle to [-pi/4, pi/4) (a cube looks the same every 90 degrees)."""
    return (yaw + math.pi / 4) % (math.pi / 2) - math.pi / 4


def observe_poses(scene: Scene, panda: Panda) -> Observation:
    """Pose-mode observation: the cubes' simulated poses and the gripper's joints."""
    blocks = []
    for i in range(scene.n):
        pose = scene.block_pose(i)
        tilt, yaw = tilt_and_yaw(pose.orientation)
        axes = tuple(tuple(float(v) for v in col) for col in rotation_matrix(pose.orientation).T)
        blocks.append(BlockObs(pose.position, tilt, yaw, axes=axes))
    return Observation(tuple(blocks), tuple(panda.ee_position()), panda.finger_width(),
                       scene.config.physics.cube_size)


# ---------------------------------------------------------------- predicates


def _flat(b: BlockObs, tol: Tolerances) -> bool:
    return b.tilt is None or b.tilt < tol.tilt


def holding(obs: Observation, x: int, tol: Tolerances = TOLERANCES) -> bool:
    """Cube x sits between closed fingers at the grasp point."""
    d = np.linalg.norm(np.subtract(obs.blocks[x].position, obs.grasp_point))
    return bool(d < tol.hold_dist and obs.finger_width < obs.size + tol.hold_width)


def on_table(obs: Observation, x: int, tol: Tolerances = TOLERANCES) -> bool:
    """Cube x rests flat on the table."""
    b = obs.blocks[x]
    return abs(b.position[2] - obs.size / 2) < tol.table_z and _flat(b, tol)


def on(obs: Observation, x: int, y: int, tol: Tolerances = TOLERANCES) -> bool:
    """Cube x rests flat on cube y."""
    bx, by = obs.blocks[x], obs.blocks[y]
    dz = bx.position[2] - by.position[2] - obs.size
    dxy = math.hypot(bx.position[0] - by.position[0], bx.position[1] - by.position[1])
    return abs(dz) < tol.stack_z and dxy < tol.stack_xy and _flat(bx, tol)


def clear(obs: Observation, x: int, tol: Tolerances = TOLERANCES) -> bool:
    """Nothing rests on cube x and it is not held."""
    n = len(obs.blocks)
    return not holding(obs, x, tol) and not any(on(obs, y, x, tol) for y in range(n) if y != x)


def gripper_closed_on_cube(obs: Observation, tol: Tolerances = TOLERANCES) -> bool:
    """The fingers stopped at a cube's width: something cube-sized is between them."""
    return obs.size - tol.hold_width < obs.finger_width < obs.size + tol.hold_width


def _resting_support(obs: Observation, x: int, tol: Tolerances) -> int | None:
    """TABLE or the cube x rests on, or None."""
    if on_table(obs, x, tol):
        return TABLE
    below = [y for y in range(len(obs.blocks)) if y != x and on(obs, x, y, tol)]
    return below[0] if len(below) == 1 else None


def interpret(obs: Observation, tol: Tolerances = TOLERANCES) -> Perceived:
    """The symbolic state of an observation, or why there is none.

    A cube near the grasp point between closed fingers is held. A cube that rests
    nowhere and that the camera cannot place (hidden by the hand, or seen only in
    part) is held when the fingers are closed on a cube and it is the only such cube.
    """
    n = len(obs.blocks)
    support: list[int | None] = [None] * n
    for x in range(n):
        if holding(obs, x, tol):
            support[x] = HAND
        elif obs.blocks[x].visible:
            if obs.blocks[x].position[2] < tol.off_table_z:
                return Perceived(None, f"block {letter(x)} fell off the table")
            support[x] = _resting_support(obs, x, tol)
    unplaced = [x for x in range(n) if support[x] is None]
    if len(unplaced) == 1 and HAND not in support and gripper_closed_on_cube(obs, tol):
        b = obs.blocks[unplaced[0]]
        near = not b.visible or float(np.linalg.norm(np.subtract(b.position, obs.grasp_point))) < tol.hold_search
        if near:
            support[unplaced[0]] = HAND
            unplaced = []
    unseen = tuple(x for x in unplaced if not obs.blocks[x].visible)
    if unseen:
        many = len(unseen) > 1
        return Perceived(None, f"unseen cube{'s' * many} {', '.join(letter(x) for x in unseen)}: no camera read "
                               f"{'their markers' if many else 'its marker'}", unseen=unseen)
    if unplaced:
        x = unplaced[0]
        where = ", ".join(f"{v:.3f}" for v in obs.blocks[x].position)
        return Perceived(None, f"block {letter(x)} is not resting flat anywhere (at {where})", stray=x)
    try:
        state = arm_state(tuple(int(s) for s in support if s is not None))
    except WorldError as exc:
        return Perceived(None, f"impossible scene: {exc}")
    for x in range(n):
        if state.support[x] != HAND and state.is_clear(x) != clear(obs, x, tol):
            return Perceived(None, f"clear({letter(x)}) disagrees with on")
    return Perceived(state)


def settled(scene: Scene, panda: Panda, tol: Tolerances = TOLERANCES) -> bool:
    """True when every cube not in the gripper is at rest."""
    for i in range(scene.n):
        lin, ang = scene.block_speed(i)
        if lin > tol.settle_linear or ang > tol.settle_angular:
            if panda.grips(scene.block_body(i)):
                continue
            return False
    return True


def state_message(state: ArmState, goal: ArmState, action_code: int = 0) -> str:
    """The message of a perceived state: the paper's form with the goal's code (n <= 6), else the large form.

    ``action_code`` fills the action slot of the paper's form; the large form's slot stays 0.
    """
    messages = Messages(goal)
    if messages.goal_index is None:
        return messages.state(state)
    return format_state_message(state, messages.goal_index, action_code)
