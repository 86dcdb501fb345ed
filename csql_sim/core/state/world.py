"""The blocks world's actions and transition, and the enumerated world of n <= 6 blocks.

States (:class:`~csql_sim.core.state.state.State`, for every n) live in
:mod:`csql_sim.core.state.state`; this module re-exports them. The four STRIPS operators act
on a state of any n (:func:`is_legal`, :func:`legal_actions`, :func:`successor`; the action
order by arithmetic: :func:`action_index`, :func:`action_at`). Up to :data:`MAX_BLOCKS`
blocks the world is also enumerated (:func:`all_states`, :class:`BlocksWorld`): the ground
index and the paper's messages are views of a state there.

The configuration notation (``CBA``, ``A,B,C``, ``B,C+A``) is written by
:func:`format_config` and read by :mod:`csql_sim.core.state.notation`.

Stable orders (they define the paper's goal code and action code):

* **States**: hand empty before holding; within each group, by the state message's
  clear, on and held fields in descending character order. For n=3 this puts
  ``A,B,C`` first (code ``0``) and the test task's goal ``BAC`` (C on A on B) at index 12,
  code ``C``, as in the paper's Figure 6.
* **Actions**: unstack(X,Y) for X, then Y in block order; pickup(X); putdown(X);
  stack(X,Y). For n=3 these are the paper's action codes 1-9, A-I in order.
"""

from __future__ import annotations

import enum
import functools
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

from csql_sim.core.state.state import (
    HAND,
    TABLE,
    State,
    WorldError,
    default_name,
)
from csql_sim.core.state.state import LETTERS as LETTERS  # re-exported: the notation's letters
from csql_sim.core.state.state import format_config as format_config  # re-exported

MIN_BLOCKS = 2
MAX_BLOCKS = 6
"""The enumeration limit: the ground world (all states, the paper's messages) is built up to 6 blocks."""
BLOCK_NAMES = "ABCDEF"
TEST_START = "CBA"
"""The paper's test task (Figure 3) starts with A on B on C ..."""
TEST_GOAL = "BAC"
"""... and ends with C on A on B (goal code ``C``); the optimal plan has 8 actions."""


def check_n(n: int) -> int:
    """Return ``n`` if it is a number of blocks the enumerated world has, else raise WorldError."""
    if not isinstance(n, int) or isinstance(n, bool) or not MIN_BLOCKS <= n <= MAX_BLOCKS:
        raise WorldError(f"number of blocks must be {MIN_BLOCKS}..{MAX_BLOCKS}, got {n!r}")
    return n


def block_name(i: int) -> str:
    """The default name of block ``i`` (0 -> 'A'; see :func:`csql_sim.core.state.state.default_name`)."""
    return default_name(i)


class ActionKind(enum.Enum):
    """The four STRIPS operators."""

    UNSTACK = "unstack"
    PICKUP = "pickup"
    PUTDOWN = "putdown"
    STACK = "stack"


@dataclass(frozen=True)
class Action:
    """One operator applied to named blocks.

    Attributes:
        kind: the operator.
        block: the block moved.
        target: for UNSTACK the block it comes from, for STACK the block it goes onto;
            None for PICKUP and PUTDOWN (the table).

    """

    kind: ActionKind
    block: int
    target: int | None = None

    @property
    def is_pick(self) -> bool:
        """True for the two operators that close the gripper on a block."""
        return self.kind in (ActionKind.PICKUP, ActionKind.UNSTACK)

    def name(self, names: Sequence[str] | None = None) -> str:
        """``pickup(A)``, ``putdown(A)``, ``unstack(A,B)`` or ``stack(A,B)`` (with ``names``: the blocks' own)."""
        call = default_name if names is None else names.__getitem__
        if self.target is None:
            return f"{self.kind.value}({call(self.block)})"
        return f"{self.kind.value}({call(self.block)},{call(self.target)})"

    def __str__(self) -> str:
        return self.name()


@dataclass(frozen=True)
class Precondition:
    """One STRIPS precondition, as data (the operators' one definition).

    Attributes:
        what: ``"clear"`` (nothing on ``block``, not held), ``"on"`` (``block`` stands on
            ``value``: a block index or :data:`TABLE`) or ``"held"`` (the gripper holds
            ``value``: a block index, or None for an empty hand).
        block: the block the condition is about (None for ``"held"``).
        value: see ``what``.
    """

    what: str
    block: int | None = None
    value: int | None = None

    def holds(self, state: State) -> bool:
        """Whether the condition is true in ``state``."""
        if self.what == "held":
            return state.held == self.value
        if self.what == "clear":
            return state.is_clear(self.block)
        return state.support[self.block] == self.value


def preconditions(action: Action) -> tuple[Precondition, ...]:
    """The STRIPS preconditions of ``action``, the one definition of them.

    :func:`is_legal` evaluates them on a state and the R-classifier generator
    (:func:`csql_sim.core.classifiers.r_classifier.precondition_condition`) writes them as a pattern.
    """
    b = action.block
    if action.kind is ActionKind.PICKUP:
        return Precondition("held"), Precondition("clear", b), Precondition("on", b, TABLE)
    if action.kind is ActionKind.UNSTACK:
        return Precondition("held"), Precondition("clear", b), Precondition("on", b, action.target)
    if action.kind is ActionKind.PUTDOWN:
        return (Precondition("held", value=b),)
    return Precondition("held", value=b), Precondition("clear", action.target)


def is_legal(state: State, action: Action) -> bool:
    """Whether ``action``'s preconditions hold in ``state`` (STRIPS semantics)."""
    return all(p.holds(state) for p in preconditions(action))


def successor(state: State, action: Action) -> State:
    """The state after ``action``; raises WorldError if it is not legal."""
    if not is_legal(state, action):
        raise WorldError(f"{action.name()} is not legal in {state.notation()}")
    support = list(state.support)
    if action.is_pick:
        support[action.block] = HAND
    elif action.kind is ActionKind.PUTDOWN:
        support[action.block] = TABLE
    else:
        support[action.block] = action.target
    return state.with_changes(tuple(support), (action.block,))


def _generate_states(n: int) -> Iterator[State]:
    """Every valid support vector (brute force over (n+2)^n candidates, n <= 6)."""
    choices = (TABLE, HAND, *range(n))

    def rec(prefix: list[int]) -> Iterator[tuple[int, ...]]:
        if len(prefix) == n:
            yield tuple(prefix)
            return
        for c in choices:
            prefix.append(c)
            yield from rec(prefix)
            prefix.pop()

    for support in rec([]):
        try:
            yield State(support)
        except WorldError:
            continue


def _message_body(state: State) -> str:
    """The clear, on and held fields of the state's message (see csql_sim.core.state.message)."""
    clear = "".join("1" if state.is_clear(i) else "0" for i in range(state.n))
    on = "".join(
        "t" if s == TABLE else "0" if s == HAND else BLOCK_NAMES[s].lower() for s in state.support
    )
    held = state.held
    return clear + on + ("0" if held is None else BLOCK_NAMES[held].lower())


def _state_sort_key(state: State) -> tuple:
    return (state.held is not None, tuple(-ord(ch) for ch in _message_body(state)))


@functools.cache
def all_states(n: int) -> tuple[State, ...]:
    """Every state of the n-block world in the stable order (22 for n=3)."""
    check_n(n)
    return tuple(sorted(_generate_states(n), key=_state_sort_key))


@functools.cache
def all_actions(n: int) -> tuple[Action, ...]:
    """Every action of the n-block world in the stable order (18 for n=3)."""
    check_n(n)
    blocks = range(n)
    out = [Action(ActionKind.UNSTACK, x, y) for x in blocks for y in blocks if x != y]
    out += [Action(ActionKind.PICKUP, x) for x in blocks]
    out += [Action(ActionKind.PUTDOWN, x) for x in blocks]
    out += [Action(ActionKind.STACK, x, y) for x in blocks for y in blocks if x != y]
    return tuple(out)


def legal_actions(state: State) -> tuple[Action, ...]:
    """The legal actions of ``state`` in the stable action order (without listing all actions)."""
    held = state.held
    if held is not None:
        onto = [Action(ActionKind.STACK, held, y) for y in range(state.n) if y != held and state.is_clear(y)]
        return (Action(ActionKind.PUTDOWN, held), *onto)
    ups = [Action(ActionKind.UNSTACK, x, s) for x, s in enumerate(state.support) if s >= 0 and state.is_clear(x)]
    picks = [Action(ActionKind.PICKUP, x) for x, s in enumerate(state.support) if s == TABLE and state.is_clear(x)]
    return (*ups, *picks)


def action_name(action: Action, names: Sequence[str] | None = None) -> str:
    """``pickup(A)``, ``unstack(Z,Y)``: :meth:`Action.name`, with the default names or ``names``."""
    return action.name(names)


def action_count(n: int) -> int:
    """Number of actions of the n-block world: unstack and stack for each ordered pair, pickup and putdown."""
    return 2 * n * (n - 1) + 2 * n


def action_index(action: Action, n: int) -> int:
    """The action's index in the stable order of :func:`all_actions`, by arithmetic (any n)."""
    pairs = n * (n - 1)
    x = action.block
    if action.kind is ActionKind.PICKUP:
        return pairs + x
    if action.kind is ActionKind.PUTDOWN:
        return pairs + n + x
    y = action.target
    pair = x * (n - 1) + y - (y > x)
    return pair if action.kind is ActionKind.UNSTACK else pairs + 2 * n + pair


def action_at(index: int, n: int) -> Action:
    """Inverse of :func:`action_index`."""
    pairs = n * (n - 1)
    if not 0 <= index < action_count(n):
        raise WorldError(f"action index {index} out of range for {n} blocks")
    if pairs <= index < pairs + 2 * n:
        kind = ActionKind.PICKUP if index < pairs + n else ActionKind.PUTDOWN
        return Action(kind, (index - pairs) % n)
    kind, pair = (ActionKind.UNSTACK, index) if index < pairs else (ActionKind.STACK, index - pairs - 2 * n)
    x, k = divmod(pair, n - 1)
    return Action(kind, x, k + (k >= x))


class BlocksWorld:
    """Index tables over one n-block world, for code that works with integers.

    Attributes:
        n: number of blocks.
        states: all states in the stable order; a state's index is its goal code.
        actions: all actions in the stable order; index + 1 is the action code.
        legal: ``legal[s]`` is the tuple of legal action indices in state ``s``.
        next_state: ``next_state[s][a]`` is the successor's index, or -1 if illegal.

    """

    def __init__(self, n: int) -> None:
        self.n = check_n(n)
        self.states = all_states(n)
        self.actions = all_actions(n)
        self._state_index = {s: i for i, s in enumerate(self.states)}
        self._action_index = {a: i for i, a in enumerate(self.actions)}
        self.legal: tuple[tuple[int, ...], ...] = tuple(
            tuple(i for i, a in enumerate(self.actions) if is_legal(s, a)) for s in self.states
        )
        table = []
        for s, acts in zip(self.states, self.legal, strict=True):
            row = [-1] * len(self.actions)
            for a in acts:
                row[a] = self._state_index[successor(s, self.actions[a])]
            table.append(tuple(row))
        self.next_state: tuple[tuple[int, ...], ...] = tuple(table)

    @classmethod
    @functools.cache
    def of(cls, n: int) -> BlocksWorld:
        """The shared, cached world for n blocks."""
        return cls(n)

    def state_index(self, state: State) -> int:
        """Index of ``state`` in :attr:`states`."""
        try:
            return self._state_index[state]
        except KeyError:
            raise WorldError(f"{state.notation()} is not a state of the {self.n}-block world") from None

    def action_index(self, action: Action) -> int:
        """Index of ``action`` in :attr:`actions`."""
        try:
            return self._action_index[action]
        except KeyError:
            raise WorldError(f"{action.name()} is not an action of the {self.n}-block world") from None
