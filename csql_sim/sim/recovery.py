"""Physical recovery: put a cube that rests flat nowhere back flat on the table.

A dropped or nudged cube can end leaning against another cube, or tilted on a cube's
edge; no blocks-world action applies to it. :class:`Flatten` re-grasps it by the two
faces that stay vertical (the faces whose normal is the cube's most horizontal axis),
lifts it clear, lowers it onto a free table spot until it touches, and lets go: the cube
drops the last millimetres and lands flat. Like the pick and place primitives it only
moves the arm; the cube moves through contact.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csql_sim.sim.perception import Observation, Perceived
from csql_sim.sim.primitives import CarryHook, Status, carry_height, free_spot, settle
from csql_sim.sim.robot import Panda
from csql_sim.sim.scene import Scene
from csql_sim.world import BLOCK_NAMES


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


def grip_yaw(obs: Observation, block: int, current: float) -> float:
    """Gripper yaw that closes the fingers along the cube's most horizontal axis."""
    b = obs.blocks[block]
    if b.axes is None:
        return current
    axes = np.asarray(b.axes)
    h = axes[int(np.argmin(np.abs(axes[:, 2])))]
    yaw = math.atan2(-h[0], h[1])  # the fingers close along the hand's y axis: (-sin yaw, cos yaw)
    candidates = [yaw + k * math.pi for k in (-2, -1, 0, 1, 2)]
    return min((y for y in candidates if abs(y) <= 2.6), key=lambda y: abs(y - current))


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
        name = BLOCK_NAMES[self.block]
        x, y, z = obs.blocks[self.block].position
        goal_z = max(z + off.grasp_above_centre, off.min_grasp_height)
        yaw = grip_yaw(obs, self.block, panda.yaw)
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


def recovery_for(perceived: Perceived) -> Flatten | None:
    """The recovery primitive for a failed perception, or None when none applies."""
    if perceived.state is None and perceived.stray is not None:
        return Flatten(perceived.stray)
    return None


__all__ = ["FLATTEN_OFFSETS", "Flatten", "FlattenOffsets", "grip_yaw", "recovery_for"]
