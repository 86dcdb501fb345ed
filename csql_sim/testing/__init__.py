"""Testing helpers for users of csql-sim: the pytest plugin with the ``arm`` fixture (:mod:`.plugin`).

The plugin is registered under pytest's ``pytest11`` entry point as ``csql_sim``; without
the entry point, load it with ``pytest -p csql_sim.testing.plugin`` or
``pytest_plugins = ["csql_sim.testing.plugin"]`` in a root ``conftest.py``.
"""
