"""GN1, a hand-written lifted baseline (Gupta and Nau 1992): a yardstick, not a learner.

"Move a misplaced clear block to its goal place if that place is ready; otherwise move a
misplaced clear block to the table, preferring blocks in a deadlock, then blocks that
uncover one needed next." In the paper's four operators a move is a pick and the put
that follows, so :class:`Gn1Policy` decides:

* **holding a block**: put it on its goal place if that place is ready
  (:func:`~csql_sim.core.state.goal_relations.goal_place_ready`), else on the table;
* **hand empty**: pick the first misplaced clear block (block order) whose goal place is
  ready; else the first misplaced clear block not on the table that is deadlocked
  (:func:`~csql_sim.core.state.goal_relations.deadlocked`), else one standing above a block
  that is "needed next" (misplaced with its goal place ready, or a well-placed goal
  support of a misplaced block), else any; it will go to the table.
* **a goal that holds a block g**: GN1 first builds the hand-empty goal with g where it
  stands (on the table, or on a block that is clear in the goal) or else on the table,
  and picks g up last.

It works on relational states of any n <= 26 and, through the same ``act``, on the
enumerated world's states (the policy contract, :class:`csql_sim.core.policies.contract.Policy`).
"""

from __future__ import annotations

from csql_sim.core.policies.contract import Policy
from csql_sim.core.state.goal_relations import deadlocked, goal_place_ready, well_placed
from csql_sim.core.state.move_relations import target_goal
from csql_sim.core.state.moves import pick_action
from csql_sim.core.state.world import TABLE, Action, ActionKind, State


def _needed_below(state: State, goal: State, placed: tuple[bool, ...], b: int) -> bool:
    """Whether some block under b is needed next (see the module docstring)."""
    supports = {goal.support[c] for c in range(state.n) if not placed[c]}
    below = state.support[b]
    while below >= 0:
        ready = not placed[below] and goal_place_ready(state, goal, placed, below)
        if ready or (placed[below] and below in supports):
            return True
        below = state.support[below]
    return False


class Gn1Policy(Policy):
    """The GN1 rules as a policy (named baseline ``gn1``; see the module docstring)."""

    name = "gn1"
    blocks: int | None = None

    def act(self, state: State, goal: State) -> Action | None:
        """The next action towards ``goal``, or None at the goal."""
        if state == goal:
            return None
        target = target_goal(state, goal)
        placed = well_placed(state, target)
        held = state.held
        if held is not None:
            d = target.support[held]
            if d != TABLE and goal_place_ready(state, target, placed, held):
                return Action(ActionKind.STACK, held, d)
            return Action(ActionKind.PUTDOWN, held)
        if state == target:
            return pick_action(state, goal.held)
        clear = [b for b in range(state.n) if not placed[b] and state.is_clear(b)]
        for b in clear:
            if goal_place_ready(state, target, placed, b):
                return pick_action(state, b)
        movable = [b for b in clear if state.support[b] != TABLE]
        stuck = deadlocked(state, target)
        for wanted in (lambda b: b in stuck, lambda b: _needed_below(state, target, placed, b), lambda b: True):
            for b in movable:
                if wanted(b):
                    return pick_action(state, b)
        return None
