"""The policy contract: what every planner of csql-sim answers, whatever it is made of.

:class:`Policy` is one small protocol: a ``name``, the number of ``blocks`` it is for (None
when any) and ``act(state, goal)``, the next action towards the goal (None at the goal).
Every policy implements it:

* the greedy table of a ground rule base (:class:`~csql_sim.core.policies.greedy_table.GreedyTable`)
  and its classifier-list twin (:class:`~csql_sim.core.policies.policy.QPolicy`);
* a goal-form rule base's default hierarchy (:class:`~csql_sim.core.policies.default_hierarchy.DefaultHierarchy`);
* a sharded rule base, read lazily (:class:`~csql_sim.core.policies.sharded_policy.ShardedPolicy`);
* lifted Q-classifiers, for any n (:class:`~csql_sim.core.policies.lifted_policy.LiftedPolicy`);
* the GN1 baseline (:class:`csql_sim.core.policies.gn1.Gn1Policy`);
* breadth-first search, the yardstick (:class:`~csql_sim.core.model.search.BfsPolicy`), which
  lies below the policies in the core's layers and so implements the protocol by its shape
  alone (``isinstance(BfsPolicy(), Policy)`` holds; the protocol is checkable at run time).

The others name it as their base class. A rule file becomes one of them through
:func:`csql_sim.core.policies.loader.load_policy`.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from csql_sim.core.state.world import Action, State


@runtime_checkable
class Policy(Protocol):
    """Anything that proposes the next action towards a goal; None at the goal.

    Attributes:
        name: what it is called in reports: ``"rules"`` (any rule file), ``"bfs"``, ``"gn1"``.
        blocks: the number of blocks it is for, or None when any.

    """

    name: str
    blocks: int | None

    def act(self, state: State, goal: State) -> Action | None:
        """The action to take in ``state`` to reach ``goal``; None at the goal."""
        ...
