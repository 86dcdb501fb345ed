"""Physical execution on a simulated Franka Panda (only :mod:`csql_sim.sim.world.client` imports pybullet).

The flow of one step: scene -> perception -> state message -> policy -> action message ->
primitive -> scene, with the world model predicting what perception should see next
(:mod:`~csql_sim.sim.control.executor`).
"""
