"""Gymnasium ids of the package's two environments: registered when :mod:`csql_sim.envs` is imported.

Gymnasium 1.x's convention (the one ``ale_py`` follows) is that importing an environment
package's module registers its ids::

    import gymnasium as gym
    import csql_sim.envs

    gym.register_envs(csql_sim.envs)
    env = gym.make("csql_sim/BlocksWorld-v0", blocks=4, render_mode="ansi")

``gym.make("csql_sim.envs:csql_sim/BlocksWorld-v0")`` imports the module itself. The ids
are strings (entry points): nothing heavy is imported until an environment is made.
``import csql_sim`` alone registers nothing. Gymnasium 0.26-0.29 also load the plugin
entry point (group ``gymnasium.envs`` in ``pyproject.toml``), which calls
:func:`register_envs` (idempotent).

Keyword arguments: ``blocks`` (2..30; past six the observations are large messages and
past 26 numeric, ``observation="numeric"``; the states relational, see
:class:`csql_sim.envs.symbolic.BlocksWorldEnv`), ``rules`` (a rule file for the dynamics or,
on the arm, the action mask; up to six blocks),
``render_mode``, ``max_steps``, ``observation`` (``"message"``, the default, or
``"numeric"``: :mod:`csql_sim.envs.numeric`); on the arm also ``perception`` (``"pose"`` or
``"camera"``), ``width`` and ``height``.

``reset(options=...)`` takes ``start`` and ``goal``, or ``problem`` (a PDDL problem file: its
start, a goal that may be partial, and its object names; :mod:`csql_sim.envs.problem`).

Both ids have a default step limit, :data:`MAX_EPISODE_STEPS` (``gymnasium.make`` wraps
the environment in ``TimeLimit``; ``max_episode_steps=...`` changes it), so a random agent's
episode ends. The entry points carry their class's ``metadata`` (:data:`BLOCKS_WORLD_METADATA`,
:data:`PANDA_BLOCKS_METADATA`), from which ``gymnasium.make`` knows the render modes without
importing the class.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from csql_sim.envs.physical import PhysicalBlocksEnv
    from csql_sim.envs.symbolic import BlocksWorldEnv

BLOCKS_WORLD_ID = "csql_sim/BlocksWorld-v0"
PANDA_BLOCKS_ID = "csql_sim/PandaBlocks-v0"
MAX_EPISODE_STEPS = 200
"""The default step limit of both ids (an optimal plan of ten blocks takes at most 36 actions)."""
BLOCKS_WORLD_METADATA = {"render_modes": ["ansi"], "render_fps": 4}
"""``BlocksWorldEnv.metadata``, known without importing the class."""
PANDA_BLOCKS_METADATA = {"render_modes": ["rgb_array"], "render_fps": 30}
"""``PhysicalBlocksEnv.metadata``, known without importing pybullet."""


def make_blocks_world(blocks: int = 3, rules: str | os.PathLike | None = None, render_mode: str | None = None,
                      max_steps: int | None = None, observation: str = "message") -> BlocksWorldEnv:
    """The entry point of ``csql_sim/BlocksWorld-v0`` (see :class:`csql_sim.envs.symbolic.BlocksWorldEnv`)."""
    from csql_sim.envs.symbolic import BlocksWorldEnv

    return BlocksWorldEnv(blocks, max_steps=max_steps, render_mode=render_mode, rules=rules, observation=observation)


def make_panda_blocks(blocks: int = 3, perception: str = "pose", rules: str | os.PathLike | None = None,
                      render_mode: str | None = None, max_steps: int | None = None, width: int = 640,
                      height: int = 480, observation: str = "message") -> PhysicalBlocksEnv:
    """The entry point of ``csql_sim/PandaBlocks-v0`` (see :class:`csql_sim.envs.physical.PhysicalBlocksEnv`)."""
    from csql_sim.envs.physical import PhysicalBlocksEnv

    return PhysicalBlocksEnv(blocks, max_steps=max_steps, render_mode=render_mode, perception=perception,
                             width=width, height=height, rules=rules, observation=observation)


make_blocks_world.metadata = BLOCKS_WORLD_METADATA  # type: ignore[attr-defined]
make_panda_blocks.metadata = PANDA_BLOCKS_METADATA  # type: ignore[attr-defined]


def register_envs() -> None:
    """Register both ids with Gymnasium (idempotent)."""
    from gymnasium.envs.registration import register, registry

    for env_id, entry_point in ((BLOCKS_WORLD_ID, "csql_sim.envs.registration:make_blocks_world"),
                                (PANDA_BLOCKS_ID, "csql_sim.envs.registration:make_panda_blocks")):
        if env_id not in registry:
            register(id=env_id, entry_point=entry_point, max_episode_steps=MAX_EPISODE_STEPS)
