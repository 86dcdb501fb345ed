"""Gymnasium environments: the symbolic blocks world and the simulated arm, and their ids.

Importing this module registers the two ids, as Gymnasium 1.x expects of an environment
package (``ale_py`` does the same)::

    import gymnasium as gym
    import csql_sim.envs

    gym.register_envs(csql_sim.envs)  # a no-op that keeps linters from flagging the import
    env = gym.make("csql_sim/BlocksWorld-v0", blocks=4)

or, in one string, ``gym.make("csql_sim.envs:csql_sim/BlocksWorld-v0")``. The ids are
strings: nothing heavy (pybullet, the symbolic world) is imported until an environment is
made. ``import csql_sim`` alone registers nothing.
"""

from csql_sim.envs.registration import BLOCKS_WORLD_ID, PANDA_BLOCKS_ID, register_envs

register_envs()

__all__ = ["BLOCKS_WORLD_ID", "PANDA_BLOCKS_ID", "register_envs"]
