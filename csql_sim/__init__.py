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
:func:`csql_sim.envs.registration.register_envs` (see the README). The top-level API,
``csql_sim.plan``, ``validate``, ``execute`` and ``train_lifted`` (:mod:`csql_sim.api`), is
imported when one of its names is first used.
"""

__version__ = "0.1.0"

_API = ("plan", "validate", "execute", "train_lifted", "Plan", "Validation", "Execution", "LiftedRules")


def __getattr__(name: str) -> object:
    """The top-level API (:mod:`csql_sim.api`), imported when one of its names is first used."""
    if name in _API:
        import importlib

        # By name, as PEP 562's lazy modules do: the root package is no layer, and the layers below
        # that read its __version__ must not appear to import the API.
        return getattr(importlib.import_module("csql_sim.api"), name)
    raise AttributeError(f"module 'csql_sim' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_API])
