"""The names of the given atoms, in condition order: strings only.

What each atom means, and its computation, is :mod:`csql_sim.core.state.move_relations`.
The names live apart so that a learner's parameters can name the atoms it may read
without importing their relations.
"""

ATOMS = ("misplaced(?x)", "goal-on(?x,?d)", "ready(?d)", "deadlocked(?x)", "above-needed(?x)", "least-stuck(?x)",
         "deadlock", "holding", "cover(?x)")
"""The relations of a move, in condition order."""

__all__ = ["ATOMS"]
