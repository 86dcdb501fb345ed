"""The move generator: which moves are legal in a state, and the actions and state of a move.

A **move** binds the variables of the lifted Q-classifiers: ``?x``, the block moved, and
``?d``, where it goes (the table or a block ``?y``). In the paper's four operators a move is
a pick and the put that follows (two actions); when a block is already held, the move is the
put alone. Nothing here reads a goal: the moves are the world's, for any learner or policy.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from csql_sim.core.state.world import HAND, TABLE, Action, ActionKind, State, is_legal

KINDS = ("table", "block")
"""A move's kind: to the table, or onto a block."""


@dataclass(frozen=True)
class Move:
    """Block ``block`` to ``onto`` (TABLE or a block index)."""

    block: int
    onto: int

    @property
    def kind(self) -> str:
        """``table`` or ``block``."""
        return "table" if self.onto == TABLE else "block"


def pick_action(state: State, b: int) -> Action:
    """The action that lifts block b from where it stands."""
    s = state.support[b]
    return Action(ActionKind.PICKUP, b) if s == TABLE else Action(ActionKind.UNSTACK, b, s)


def put_action(move: Move) -> Action:
    """The action that puts the moved block down."""
    if move.onto == TABLE:
        return Action(ActionKind.PUTDOWN, move.block)
    return Action(ActionKind.STACK, move.block, move.onto)


def after(state: State, move: Move) -> State:
    """The hand-empty state after ``move`` (the pick, if any, and the put)."""
    support = list(state.support)
    support[move.block] = move.onto
    return State(tuple(support))


def moves(state: State) -> tuple[Move, ...]:
    """The legal moves: the held block's puts, or every clear block to the table and onto every other clear block."""
    return legal_moves(state.held, [b for b in range(state.n) if state.is_clear(b)], state.support)


def legal_moves(held: int | None, clear: Sequence[int], support: Sequence[int]) -> tuple[Move, ...]:
    """:func:`moves` from the relations: the held block (or None), the clear blocks in order, the supports."""
    movers = [held] if held is not None else clear
    out = []
    for x in movers:
        if support[x] != TABLE:
            out.append(Move(x, TABLE))
        out.extend(Move(x, y) for y in clear if y != x and support[x] != y)
    return tuple(out)


def last_action(state: State, goal: State) -> Action | None:
    """The one legal action that leads from ``state`` to ``goal``, if there is one (one action of lookahead).

    Only the goal is read: the action is the task's last, the one whose reward ends it.
    """
    diff = [b for b, (s, g) in enumerate(zip(state.support, goal.support, strict=True)) if s != g]
    if len(diff) != 1:
        return None
    b, onto = diff[0], goal.support[diff[0]]
    if onto == HAND:
        action = pick_action(state, b)
    elif state.held == b:
        action = put_action(Move(b, onto))
    else:
        return None
    return action if is_legal(state, action) else None


__all__ = ["KINDS", "Move", "after", "last_action", "legal_moves", "moves", "pick_action", "put_action"]
