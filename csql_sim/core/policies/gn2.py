"""GN2, the best hand-written linear-time planner for the blocks world: a yardstick, not a learner.

Slaney and Thiébaux, "Blocks World revisited", Artificial Intelligence 125 (2001) 119-153,
describe the near-optimal planners of the domain in terms of **constructive moves** (a
misplaced block moved to its goal place, which is ready: the table, or a clear block in its
goal position) and **deadlocks** (Gupta and Nau 1992: misplaced blocks each of which must
leave its place before another can make its final move; at least one block of every
deadlock goes to the table first, and the set of table visitors is a hitting set of the
deadlocks):

* **GN1** (:class:`csql_sim.core.policies.gn1.Gn1Policy`): make a constructive move while there
  is one; otherwise move a clear deadlocked block to the table;
* **GN2** (this module) is GN1 with a better choice in the non-constructive case: among the
  clear deadlocked blocks it moves to the table one whose departure makes a constructive
  move possible at once, when there is one; otherwise, as GN1, the first clear deadlocked
  block. (When no constructive move exists some clear block is deadlocked, so the last
  fallback, any misplaced clear block, is a guard only.)

Written from that description, not from the authors' code. The lookahead is one move and
costs O(1) per candidate: moving b to the table changes only the block c under b, which
becomes clear, so it enables a constructive move exactly when c is misplaced and its goal
place is ready, or c is in its goal position and the block that goes on c in the goal is
clear and misplaced.

In the paper's four operators a move is a pick and the put that follows, as in GN1: holding
a block, :class:`Gn2Policy` puts it on its goal place if that is ready, else on the table;
a goal that holds a block is reached through :func:`~csql_sim.core.state.move_relations.towards`.
The relations (well placed, clear, deadlocked) are kept up to date move by move by
:class:`~csql_sim.core.state.relation_tracker.RelationTracker` (the deadlock graph's cycles
are found by one compiled linear pass per state), so a plan of a 1,000-block tower takes
seconds.
"""

from __future__ import annotations

from csql_sim.core.policies.contract import Policy
from csql_sim.core.state.move_relations import pick_action, towards
from csql_sim.core.state.relation_tracker import KeptRelations, RelationTracker
from csql_sim.core.state.world import TABLE, Action, ActionKind, State


def constructive(tracker: RelationTracker, b: int) -> bool:
    """Whether block b is misplaced, clear and its goal place is ready (a move of b to it is constructive)."""
    if tracker.placed[b] or b not in tracker.clear:
        return False
    d = tracker.goal[b]
    return d == TABLE or (d >= 0 and d != b and tracker.placed[d] and d in tracker.clear)


def enables_constructive(tracker: RelationTracker, b: int) -> bool:
    """Whether moving clear block b (not on the table) to the table makes a constructive move possible.

    Only the block c under b changes (it becomes clear): a constructive move of c, or onto c.
    """
    c = tracker.sup[b]
    if c < 0:
        return False
    if not tracker.placed[c]:
        d = tracker.goal[c]
        return d == TABLE or (d >= 0 and d != b and tracker.placed[d] and d in tracker.clear)
    x = tracker.goal_above[c]
    return x is not None and x != b and not tracker.placed[x] and x in tracker.clear


def gn2_block(tracker: RelationTracker) -> int | None:
    """The block GN2 moves next in a hand-empty state (module docstring), or None if none is misplaced."""
    clear = sorted(tracker.clear)
    for b in clear:
        if constructive(tracker, b):
            return b
    stuck = tracker.stuck
    movable = [b for b in clear if not tracker.placed[b] and tracker.sup[b] != TABLE]
    enabling = {b for b in movable if enables_constructive(tracker, b)}
    for wanted in (lambda b: b in stuck and b in enabling, lambda b: b in stuck, lambda b: b in enabling,
                   tracker.above_needed, lambda b: True):
        for b in movable:
            if wanted(b):
                return b
    return None


class Gn2Policy(Policy):
    """The GN2 rules as a policy (named baseline ``gn2``; see the module docstring)."""

    name = "gn2"
    blocks: int | None = None

    def __init__(self) -> None:
        self._kept = KeptRelations()

    def act(self, state: State, goal: State) -> Action | None:
        """The next action towards ``goal``, or None at the goal."""
        target, last = towards(state, goal)
        if target is None:
            return last
        tracker = self._kept.of(state, target)
        held = state.held
        if held is not None:
            d = target.support[held]
            ready = d != TABLE and tracker.placed[d] and d in tracker.clear
            action = Action(ActionKind.STACK, held, d) if ready else Action(ActionKind.PUTDOWN, held)
        else:
            b = gn2_block(tracker)
            action = None if b is None else pick_action(state, b)
        self._kept.chose(action)
        return action
