"""csql-sim: classifier-system Q-learning on the blocks world, executed on a simulated arm.

Importing the package registers the Gymnasium environments ``csql_sim/BlocksWorld-v0``
and ``csql_sim/PandaBlocks-v0`` (:mod:`csql_sim.registration`; pybullet is imported only
when the physical one is made).
"""

from csql_sim.registration import register_envs

__version__ = "0.1.0"

register_envs()
