"""Rule discovery: exploring a world and inducing R-classifiers from the transitions.

:mod:`~csql_sim.discovery.world` states what discovery needs from a world to act in; the
symbolic world is here, the arm implements the same protocol in :mod:`csql_sim.sim`.
"""
