"""The start layout: where the cubes of a start configuration are placed, and where putdowns go.

:func:`start_layout` computes one :class:`Placement` per cube (towers side by side at
``LayoutConfig.tower_x``, or on the arc of :data:`~csql_sim.sim.world.config.WIDE_LAYOUT` for 7..10
cubes, on every other place of the ring of :data:`~csql_sim.sim.world.config.RING_LAYOUT` past ten; a held
block aside on the table for the caller to grasp), with
optional jitter drawn from the episode's generator; :func:`place_towers` puts the cubes
of a scene there. Placing cubes is scene construction, never part of an episode.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csql_sim.sim.world.arm_state import ArmState, SimError
from csql_sim.sim.world.config import SimConfig
from csql_sim.sim.world.scene import Scene, quaternion_from_euler

LIFT = 1e-4  # m: cubes are placed this far above their support and settle onto it


@dataclass(frozen=True)
class Placement:
    """Where one cube starts.

    Attributes:
        block: the block index.
        x: centre x, m.
        y: centre y, m.
        z: centre z, m.
        yaw: rotation about z, rad.
    """

    block: int
    x: float
    y: float
    z: float
    yaw: float = 0.0


def arc_place(config: SimConfig, i: int) -> tuple[float, float, float]:
    """The i-th place of the arc layout: (x, y, yaw), the yaw facing the arm's base."""
    lay = config.layout
    angle = (i - (lay.arc_positions - 1) / 2) * lay.arc_spacing / lay.arc_radius
    return lay.arc_radius * math.cos(angle), lay.arc_radius * math.sin(angle), angle


def _arc_index(config: SimConfig, k: int, count: int) -> int:
    """The arc place of the k-th of ``count`` start towers: the middle places, ``tower_gap`` apart if they fit."""
    places = config.layout.arc_positions
    if count > places:
        raise SimError(f"{count} start towers do not fit on the arc's {places} places")
    gap = min(config.layout.tower_gap, (places - 1) // (count - 1)) if count > 1 else 1
    return k * gap + (places - (count - 1) * gap - 1) // 2


def tower_slot(config: SimConfig, k: int, count: int) -> tuple[float, float]:
    """The xy of the k-th of ``count`` start towers (a row along y, or the middle places of the arc)."""
    lay = config.layout
    if lay.arc_radius > 0:
        return arc_place(config, _arc_index(config, k, count))[:2]
    return lay.tower_x, (k - (count - 1) / 2) * lay.tower_spacing


def slot_yaw(config: SimConfig, k: int, count: int) -> float:
    """The yaw of the cubes of the k-th of ``count`` start towers: 0 in a row, facing the base on the arc."""
    if config.layout.arc_radius > 0:
        return arc_place(config, _arc_index(config, k, count))[2]
    return 0.0


def spot_yaw(config: SimConfig, x: float, y: float, held_yaw: float) -> float:
    """The yaw a cube put down at (x, y) should land with: its own in a row layout, facing the base on the arc."""
    return math.atan2(y, x) if config.layout.arc_radius > 0 else held_yaw


def putdown_spots(config: SimConfig) -> list[tuple[float, float]]:
    """Every candidate spot of a putdown, in a fixed order (the grid of a row layout, or the arc's places)."""
    lay = config.layout
    if lay.arc_radius > 0:
        return [arc_place(config, i)[:2] for i in range(lay.arc_positions)]
    return [(x, y) for x in lay.free_x for y in lay.free_y]


def start_layout(state: ArmState, config: SimConfig, rng: np.random.Generator | None = None,
                 jitter: bool = False) -> list[Placement]:
    """The placements building the hand-empty part of ``state``; a held block stands aside.

    Args:
        state: the configuration to build.
        config: the scene's settings (cube size, tower slots, jitter bounds).
        rng: the generator for jitter.
        jitter: offset every tower cube by up to LayoutConfig.jitter_xy / jitter_yaw.
    """
    lay = config.layout
    size = config.physics.cube_size
    towers = list(state.towers())
    held = state.held
    slots = len(towers) + (1 if held is not None else 0)
    placed: list[Placement] = []
    for k, tower in enumerate(towers):
        x, y = tower_slot(config, k, slots)
        face = slot_yaw(config, k, slots)
        for level, block in enumerate(tower):
            dx = dy = yaw = 0.0
            if jitter and rng is not None:
                dx, dy = rng.uniform(-lay.jitter_xy, lay.jitter_xy, size=2)
                yaw = rng.uniform(-lay.jitter_yaw, lay.jitter_yaw)
            placed.append(Placement(block, x + dx, y + dy, size / 2 + level * size + LIFT, face + yaw))
    if held is not None:
        x, y = tower_slot(config, slots - 1, slots)
        placed.append(Placement(held, x, y, size / 2 + LIFT, slot_yaw(config, slots - 1, slots)))
    return placed


def place_towers(scene: Scene, state: ArmState, rng: np.random.Generator | None = None, jitter: bool = False) -> None:
    """Put the scene's cubes at :func:`start_layout` of ``state``, at rest."""
    for p in start_layout(state, scene.config, rng, jitter):
        scene.set_block_pose(p.block, (p.x, p.y, p.z), quaternion_from_euler((0.0, 0.0, p.yaw)))
        scene.stop_body(scene.block_body(p.block))


__all__ = ["Placement", "arc_place", "place_towers", "putdown_spots", "slot_yaw", "spot_yaw", "start_layout",
           "tower_slot"]
