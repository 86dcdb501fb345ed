"""Physical execution on a simulated Franka Panda (only :mod:`csql_sim.sim.world.client` imports pybullet).

One subpackage per family, importing downwards only (control > video > perception > world):
:mod:`~csql_sim.sim.world` (client, scene, arm), :mod:`~csql_sim.sim.perception`,
:mod:`~csql_sim.sim.video` and :mod:`~csql_sim.sim.control`. The flow of one step: scene ->
perception -> state message -> policy -> action message -> primitive -> scene, with the world
model predicting what perception should see next (:mod:`~csql_sim.sim.control.executor`).
Outside ``sim``, a family is imported through its ``__init__``.
"""
