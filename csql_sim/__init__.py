"""csql-sim: classifier-system Q-learning on the blocks world, executed on a simulated arm.

The package's folders are its layers, each importing only from the ones below it
(``docs/architecture.md``; checked by ``lint-imports``)::

    cli        the ``csql-sim`` command line
    jobs       evaluate, experiment (Figure 7), scaling, render, bench, discovery on the arm
    envs       the Gymnasium environments and their ids
    sim        the simulated Panda (the only package that imports pybullet)
    discovery | learners   rule discovery; the paper's learners behind one contract
    core       messages, classifiers, world model, symbolic search, policies, rule files
    infra      errors, guarded files, provenance, worker pools, backends

Importing the package has no side effects: the Gymnasium ids are registered by
:func:`csql_sim.envs.registration.register_envs` (see the README).
"""

__version__ = "0.1.0"
