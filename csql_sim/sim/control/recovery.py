"""Physical recovery: undo what the four blocks-world operators cannot.

* A dropped or nudged cube can end leaning against another cube, or tilted on a cube's
  edge; no blocks-world action applies to it. :class:`Flatten` re-grasps it by the two
  faces that stay vertical (the faces whose normal is the cube's most horizontal axis),
  lifts it clear, lowers it onto a free table spot until it touches, and lets go: the
  cube drops the last millimetres and lands flat.
* A nudged cube can end so close to a tower that the open hand fits nowhere around it,
  and every pick of it stops on a collision. :class:`Drag` presses the closed fingertips
  on the cube's top and slides it away from its neighbours (friction of the pads).

Like the pick and place primitives they only move the arm; cubes move through contact.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csql_sim.sim.control.primitives import CarryHook, Status, carry_height, free_spot, settle
from csql_sim.sim.perception.poses import Observation, Perceived
from csql_sim.sim.world.arm_state import letter
from csql_sim.sim.world.robot import Panda, YawFit, row_fit
from csql_sim.sim.world.scene import Scene


@dataclass(frozen=True)
class FlattenOffsets:
    """Named offsets of the flattening re-grasp, in metres."""

    grasp_above_centre: float = 0.0  # grasp point above the cube's centre
    grasp_opening: float = 0.08  # finger opening while descending (a tilted cube is wider)
    min_grasp_height: float = 0.014  # grasp point never lower than this above the table
    lift: float = 0.05  # held cube's lowest point above the highest other cube while moving
    release_gap: float = 0.004  # lower the cube until this near the table (or a touch)
    descend_stop_early: float = 0.015  # a guard stop further than this from target is a failure


FLATTEN_OFFSETS = FlattenOffsets()


def grip_yaw(obs: Observation, block: int, current: float, fit: YawFit = row_fit) -> float:
    """Gripper yaw that closes the fingers along the cube's most horizontal axis (``fit``: the wrist's range)."""
    b = obs.blocks[block]
    if b.axes is None:
        return current
    axes = np.asarray(b.axes)
    h = axes[int(np.argmin(np.abs(axes[:, 2])))]
    yaw = math.atan2(-h[0], h[1])  # the fingers close along the hand's y axis: (-sin yaw, cos yaw)
    candidates = [yaw + k * math.pi for k in (-2, -1, 0, 1, 2)]
    return min((y for y in candidates if fit(y) == y), key=lambda y: abs(y - current))


class Flatten:
    """Re-grasp a cube that rests flat nowhere and set it down flat on a free table spot."""

    name = "flatten"

    def __init__(self, block: int, offsets: FlattenOffsets = FLATTEN_OFFSETS) -> None:
        self.block = block
        self.offsets = offsets

    def __call__(self, scene: Scene, panda: Panda, obs: Observation, rng: np.random.Generator,
                 carry_hook: CarryHook | None = None) -> Status:
        start = scene.steps
        cc = scene.config.control
        off = self.offsets
        body = scene.block_body(self.block)
        name = letter(self.block)
        x, y, z = obs.blocks[self.block].position
        goal_z = max(z + off.grasp_above_centre, off.min_grasp_height)
        yaw = grip_yaw(obs, self.block, panda.yaw, panda.wrist_fit(x, y))
        high = carry_height(obs, None) + off.lift
        panda.open(off.grasp_opening)
        panda.move_to((x, y, high), yaw, cc.move_speed, cc.move_steps)
        arrived = panda.move_to((x, y, goal_z), yaw, cc.descend_speed, cc.descend_steps,
                                guard=lambda: bool(panda.touching() - {body}))
        if arrived == "guard" and panda.ee_position()[2] - goal_z > off.descend_stop_early:
            panda.move_to((x, y, high), yaw, cc.descend_speed, cc.descend_steps)
            return Status(False, f"collision while reaching the tilted {name}", scene.steps - start)
        if not panda.close(body):
            panda.open()
            panda.move_to((x, y, high), yaw, cc.descend_speed, cc.descend_steps)
            settle(scene, panda)
            return Status(False, f"re-grasp of {name} missed", scene.steps - start)
        panda.move_to((x, y, high), yaw, cc.descend_speed, cc.descend_steps)
        spot = free_spot(obs, self.block, scene, rng)
        if spot is None or not panda.grips(body):
            panda.open()
            settle(scene, panda)
            return Status(False, f"{name} slipped out of the re-grasp" if spot else "no free spot on the table",
                          scene.steps - start)
        panda.move_to((spot[0], spot[1], high), yaw, cc.move_speed, cc.move_steps, during=carry_hook)
        others = {scene.bodies["table"]} | {scene.block_body(i) for i in range(scene.n) if i != self.block}
        low = obs.size / 2 + off.release_gap
        panda.move_to((spot[0], spot[1], low), yaw, cc.descend_speed, cc.descend_steps,
                      guard=lambda: bool(scene.contact_bodies(body) & others))
        panda.open()
        panda.move_to((spot[0], spot[1], high), yaw, cc.descend_speed, cc.descend_steps)
        settle(scene, panda)
        return Status(True, "", scene.steps - start)


@dataclass(frozen=True)
class DragOffsets:
    """Named offsets of the drag, in metres."""

    contact_ahead: float = 0.016  # fingertips ahead of the cube's centre, in the drag direction
    reach_below_top: float = 0.01  # the guarded descent aims this far below the cube's top
    press: float = 0.004  # after the pads touch the top, aim this much lower: they press on it
    distance: float = 0.05  # how far to slide the cube
    neighbourhood: float = 0.15  # cubes nearer than this push the drag direction away from them


DRAG_OFFSETS = DragOffsets()


def drag_direction(obs: Observation, block: int, offsets: DragOffsets = DRAG_OFFSETS) -> np.ndarray | None:
    """Unit horizontal direction away from the cubes around ``block`` (nearer ones weigh more)."""
    c = np.asarray(obs.blocks[block].position[:2])
    away = np.zeros(2)
    for i, b in enumerate(obs.blocks):
        delta = c - np.asarray(b.position[:2])
        dist = float(np.linalg.norm(delta))
        if i != block and b.visible and 1e-6 < dist < offsets.neighbourhood:
            away += delta / dist**2
    norm = float(np.linalg.norm(away))
    return away / norm if norm > 1e-9 else None


class Drag:
    """Slide a cube that the hand cannot reach around away from its neighbours."""

    name = "drag"

    def __init__(self, block: int, offsets: DragOffsets = DRAG_OFFSETS) -> None:
        self.block = block
        self.offsets = offsets

    def __call__(self, scene: Scene, panda: Panda, obs: Observation, rng: np.random.Generator,
                 carry_hook: CarryHook | None = None) -> Status:
        start = scene.steps
        cc = scene.config.control
        off = self.offsets
        body = scene.block_body(self.block)
        d = drag_direction(obs, self.block, off)
        if d is None:
            return Status(False, f"nothing to drag {letter(self.block)} away from", 0)
        x, y, z = obs.blocks[self.block].position
        yaw = math.atan2(d[1], d[0])  # fingers close across the drag: the palm lies along it, away from the others
        fit = panda.wrist_fit(x, y)
        yaw = min((yaw + k * math.pi for k in (-1, 0, 1)), key=lambda v: abs(v - panda.yaw) if fit(v) == v else 9.0)
        px, py = x + d[0] * off.contact_ahead, y + d[1] * off.contact_ahead
        below_top = z + obs.size / 2 - off.reach_below_top  # descend until the pads touch (never this low)
        high = carry_height(obs, None)
        panda.set_fingers(0.0)
        panda.move_to((px, py, high), yaw, cc.move_speed, cc.move_steps)
        panda.move_to((px, py, below_top), yaw, cc.descend_speed / 2, cc.descend_steps * 2,
                      guard=lambda: bool(panda.touching()))
        if panda.touching() != {body}:
            panda.move_to((px, py, high), yaw, cc.descend_speed, cc.descend_steps)
            return Status(False, f"could not press on {letter(self.block)}", scene.steps - start)
        press_z = float(panda.ee_position()[2]) - off.press
        panda.move_to((px, py, press_z), yaw, cc.descend_speed / 3, cc.descend_steps)
        behind = panda.touching() - {body}  # brushed while pressing: the drag moves away from it
        tx, ty = px + d[0] * off.distance, py + d[1] * off.distance
        panda.move_to((tx, ty, press_z), yaw, cc.descend_speed / 3, cc.descend_steps * 2,
                      guard=lambda: bool(panda.touching() - {body} - behind))
        panda.move_to((tx, ty, high), yaw, cc.descend_speed, cc.descend_steps)
        panda.open()
        settle(scene, panda)
        return Status(True, "", scene.steps - start)


def recovery_for(perceived: Perceived) -> Flatten | None:
    """The recovery primitive for a failed perception, or None when none applies."""
    if perceived.state is None and perceived.stray is not None:
        return Flatten(perceived.stray)
    return None


__all__ = ["DRAG_OFFSETS", "FLATTEN_OFFSETS", "Drag", "DragOffsets", "Flatten", "FlattenOffsets", "drag_direction",
           "grip_yaw", "recovery_for"]
