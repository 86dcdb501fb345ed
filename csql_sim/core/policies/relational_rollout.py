"""Running a policy on relational states (n <= 26), symbolically, until the goal, a loop or a cap.

The relational counterpart of :func:`csql_sim.core.policies.rollout.rollout` for worlds too large to
enumerate: the states are :class:`~csql_sim.core.state.state.State` records and every
next state comes from a world model of lifted rules
(:class:`~csql_sim.core.model.lifted_model.LiftedWorldModel`, by default the four schemas).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from csql_sim.core.classifiers.lifted_rule import BLOCKS_WORLD
from csql_sim.core.model.lifted_model import LiftedWorldModel
from csql_sim.core.state.world import Action, State, WorldError


class RelationalPolicy(Protocol):
    """A policy over relational states: the next action towards ``goal``, None at the goal."""

    name: str

    def act(self, state: State, goal: State) -> Action | None:
        """The action to take in ``state``."""
        ...


@dataclass(frozen=True)
class RelationalRollout:
    """One symbolic run of a policy.

    Attributes:
        actions: the actions taken.
        reached: whether the goal was reached.
        reason: why not ("" when reached).
    """

    actions: tuple[Action, ...]
    reached: bool
    reason: str = ""

    @property
    def length(self) -> int | None:
        """The plan's length, or None when it did not reach the goal."""
        return len(self.actions) if self.reached else None


def default_cap(n: int) -> int:
    """A step cap no sensible plan reaches: every block moved three times, four steps a move."""
    return 12 * n + 4


def rollout_relational(policy: RelationalPolicy, start: State, goal: State, cap: int | None = None,
                       model: LiftedWorldModel | None = None, hand: bool = True) -> RelationalRollout:
    """Follow ``policy`` from ``start`` until ``goal``, a revisited state, an illegal action or ``cap`` steps.

    With ``hand`` False (a policy of the hand-less move domain, whose moves are executed as a pick
    and a put) only hand-empty states count as revisited: a held state lies between a move's two
    actions and is not a state of that domain, so moving one block twice in a row is no loop.
    """
    if start.n != goal.n:
        raise WorldError(f"start has {start.n} blocks but goal has {goal.n}")
    model = model or LiftedWorldModel(BLOCKS_WORLD)
    cap = default_cap(start.n) if cap is None else cap
    state, taken, seen = start, [], {start}
    while state != goal:
        if len(taken) >= cap:
            return RelationalRollout(tuple(taken), False, f"step cap {cap} reached")
        action = policy.act(state, goal)
        if action is None:
            return RelationalRollout(tuple(taken), False, f"no action in {state.named_notation()}")
        if not model.is_legal(state, action):
            return RelationalRollout(tuple(taken), False, f"illegal action in {state.named_notation()}")
        taken.append(action)
        state = model.successor(state, action)
        if state in seen and (hand or state.held is None):
            return RelationalRollout(tuple(taken), False, f"loop at {state.named_notation()}")
        seen.add(state)
    return RelationalRollout(tuple(taken), True)
