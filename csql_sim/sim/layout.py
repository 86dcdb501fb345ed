"""The start layout: where the cubes of a start configuration are placed.

:func:`start_layout` computes one :class:`Placement` per cube (towers side by side at
``LayoutConfig.tower_x``, a held block aside on the table for the caller to grasp), with
optional jitter drawn from the episode's generator; :func:`place_towers` puts the cubes
of a scene there. Placing cubes is scene construction, never part of an episode.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csql_sim.core.world import State
from csql_sim.sim.config import SimConfig
from csql_sim.sim.scene import Scene, quaternion_from_euler

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


def tower_slot(config: SimConfig, k: int, count: int) -> tuple[float, float]:
    """The xy of the k-th of ``count`` start towers."""
    lay = config.layout
    return lay.tower_x, (k - (count - 1) / 2) * lay.tower_spacing


def start_layout(state: State, config: SimConfig, rng: np.random.Generator | None = None,
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
        for level, block in enumerate(tower):
            dx = dy = yaw = 0.0
            if jitter and rng is not None:
                dx, dy = rng.uniform(-lay.jitter_xy, lay.jitter_xy, size=2)
                yaw = rng.uniform(-lay.jitter_yaw, lay.jitter_yaw)
            placed.append(Placement(block, x + dx, y + dy, size / 2 + level * size + LIFT, yaw))
    if held is not None:
        x, y = tower_slot(config, slots - 1, slots)
        placed.append(Placement(held, x, y, size / 2 + LIFT))
    return placed


def place_towers(scene: Scene, state: State, rng: np.random.Generator | None = None, jitter: bool = False) -> None:
    """Put the scene's cubes at :func:`start_layout` of ``state``, at rest."""
    for p in start_layout(state, scene.config, rng, jitter):
        scene.set_block_pose(p.block, (p.x, p.y, p.z), quaternion_from_euler((0.0, 0.0, p.yaw)))
        scene.stop_body(scene.block_body(p.block))


__all__ = ["Placement", "place_towers", "start_layout", "tower_slot"]
