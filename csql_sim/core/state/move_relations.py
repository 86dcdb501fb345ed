"""Moves and the relations that describe them: what a lifted Q-classifier's condition reads.

The legal moves are :mod:`csql_sim.core.state.moves`'s (the move generator: ``?x``, the
block moved, and ``?d``, where it goes). Moves are judged towards the **target**, the goal without a held block
(:func:`target_goal`); a goal that holds a block ends with that block's pick.

The relations of a move, in this order, are the atoms a condition tests (``1`` holds,
``0`` does not, ``#`` either; their names are :data:`~csql_sim.core.state.atom_names.ATOMS`):

====================  ===================================================================
``misplaced(?x)``     ?x is not well placed (:func:`~csql_sim.core.state.goal_relations.well_placed`)
``goal-on(?x,?d)``    ?d is ?x's support in the target
``ready(?d)``         ?d is the table, or a well-placed block with nothing on it
``deadlocked(?x)``    ?x is on a cycle of the deadlock graph
                      (:func:`~csql_sim.core.state.goal_relations.deadlocked`; a held block
                      counts as standing on the table)
``above-needed(?x)``  a block under ?x is needed next: misplaced with its goal place
                      ready, or the well-placed goal support of a misplaced block
``least-stuck(?x)``   one move of lookahead, for moves to the table: after this move,
                      no other move to the table would leave fewer blocks deadlocked
``deadlock``          some block is deadlocked (a relation of the state, not the move:
                      it tells states that need a detour from those that do not)
``holding``           the move is the put of a held block (the decision after a pick)
``cover(?x)``         ?x is in the deadlock cover: a minimal set of table visitors that
                      removes every deadlock, chosen by a fixed greedy rule
                      (:func:`~csql_sim.core.state.deadlock_cover.deadlock_cover`)
====================  ===================================================================

The move's kind (``table`` or ``block``) is the classifier's action, not an atom. The
lookahead is one move through the lifted world model; nothing searches further.
"""

from __future__ import annotations

from csql_sim.core.state.deadlock_cover import deadlock_cover
from csql_sim.core.state.goal_relations import deadlocked, well_placed
from csql_sim.core.state.moves import Move, after, moves, pick_action
from csql_sim.core.state.world import TABLE, Action, State


def target_goal(state: State, goal: State) -> State:
    """The goal without its held block g: g where it stands if nothing must go on it there, else on the table."""
    g = goal.held
    if g is None:
        return goal
    s = state.support[g]
    keep = s >= 0 and goal.above_of[s] is None
    support = list(goal.support)
    support[g] = s if keep else TABLE
    return State(tuple(support))


def towards(state: State, goal: State) -> tuple[State | None, Action | None]:
    """What a lifted policy plans towards: ``(target, None)``; or ``(None, last action)`` when it is done.

    At the goal the last action is None; at the target of a goal that holds a block, it is that block's pick.
    """
    if state == goal:
        return None, None
    target = target_goal(state, goal)
    if state == target:
        return None, pick_action(state, goal.held)
    return target, None


def _needed_below(state: State, target: State, placed: tuple[bool, ...], b: int) -> bool:
    supports = {target.support[c] for c in range(state.n) if not placed[c]}
    below = state.support[b]
    while below >= 0:
        if placed[below] and below in supports:
            return True
        if not placed[below] and _ready(state, placed, target.support[below], below):
            return True
        below = state.support[below]
    return False


def _ready(state: State, placed: tuple[bool, ...], d: int, mover: int) -> bool:
    """Whether ``d`` can take ``mover`` for good: the table, or a clear well-placed block."""
    if d == TABLE:
        return True
    return d >= 0 and d != mover and placed[d] and state.is_clear(d)


class MoveRelations:
    """The relations of every legal move of one state towards one target (the given atoms)."""

    def __init__(self, state: State, target: State) -> None:
        self.state, self.target = state, target
        self.placed = well_placed(state, target)
        held = state.held  # a held block counts as standing on the table for the deadlock graph
        self.stuck = deadlocked(state if held is None else after(state, Move(held, TABLE)), target)
        self.moves = moves(state)
        stuck_after = {m: len(deadlocked(after(state, m), target)) for m in self.moves if m.onto == TABLE}
        self.least = min(stuck_after.values(), default=0)
        self.stuck_after = stuck_after
        self.cover = deadlock_cover(state, target) if self.stuck else frozenset()

    def bits(self, move: Move) -> tuple[int, ...]:
        """The move's relations, 1 or 0 each, in the order of the atoms' names."""
        s, t, x, d = self.state, self.target, move.block, move.onto
        return (
            int(not self.placed[x]),
            int(t.support[x] == d),
            int(_ready(s, self.placed, d, x)),
            int(x in self.stuck),
            int(_needed_below(s, t, self.placed, x)),
            int(d == TABLE and self.stuck_after[move] == self.least),
            int(bool(self.stuck)),
            int(s.held is not None),
            int(x in self.cover),
        )

    def candidates(self) -> list[tuple[Move, tuple[int, ...]]]:
        """Every legal move with its relations, in move order."""
        return [(m, self.bits(m)) for m in self.moves]

    def misplaced(self) -> int:
        """The number of misplaced blocks: a lower bound on the moves still needed."""
        return self.placed.count(False)
