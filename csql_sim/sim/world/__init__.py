"""The physical world: the physics client, the scene, the arm and where the cubes stand.

:mod:`.client` is the only module that imports pybullet; :mod:`.config` holds the physical
constants, :mod:`.scene` the table and the cubes, :mod:`.robot` the Panda, :mod:`.layout`
where towers and put-down spots are, :mod:`.legend` the cubes' colours by name, :mod:`.arm_state`
the symbolic side of the arm's world (its blocks, state messages and world model).

Contract: the bottom of ``sim``: imports only ``core`` and ``infra``. Outside ``sim``, import
these names from this package (importing it does not load pybullet).
"""

from csql_sim.sim.world.arm_state import (
    ArmState,
    arm_optimal_length,
    check_arm_blocks,
    check_arm_policy,
    parse_arm_state,
    world_model_for,
)
from csql_sim.sim.world.config import MAX_ARM_BLOCKS, MAX_TOWER_HEIGHT
from csql_sim.sim.world.legend import cube_legend, legend_line
from csql_sim.sim.world.tower_height import check_tower_heights, goal_height, tower_height

__all__ = [
    "ArmState", "MAX_ARM_BLOCKS", "MAX_TOWER_HEIGHT", "arm_optimal_length", "check_arm_blocks", "check_arm_policy",
    "check_tower_heights", "cube_legend", "goal_height", "legend_line", "parse_arm_state", "tower_height",
    "world_model_for",
]
