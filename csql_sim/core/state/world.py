"""The blocks world for n blocks: states, actions, the transition, and the notation.

A state says, for every block, what it stands on: the table, another block, or the
gripper (held). At most one block is held. States are immutable and hashable; the
transition :func:`successor` is a pure function of (state, action).

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
from collections.abc import Iterator
from dataclasses import dataclass

from csql_sim.infra.errors import CsqlError

TABLE = -1
"""Support value: the block stands on the table."""
HAND = -2
"""Support value: the block is held by the gripper."""

MIN_BLOCKS = 2
MAX_BLOCKS = 6
BLOCK_NAMES = "ABCDEF"
TEST_START = "CBA"
"""The paper's test task (Figure 3) starts with A on B on C ..."""
TEST_GOAL = "BAC"
"""... and ends with C on A on B (goal code ``C``); the optimal plan has 8 actions."""


class WorldError(CsqlError):
    """A state, action or configuration that does not exist in the blocks world."""


def check_n(n: int) -> int:
    """Return ``n`` if it is a supported number of blocks, else raise WorldError."""
    if not isinstance(n, int) or isinstance(n, bool) or not MIN_BLOCKS <= n <= MAX_BLOCKS:
        raise WorldError(f"number of blocks must be {MIN_BLOCKS}..{MAX_BLOCKS}, got {n!r}")
    return n


def block_name(i: int) -> str:
    """The letter of block ``i`` (0 -> 'A')."""
    return BLOCK_NAMES[i]


@dataclass(frozen=True)
class State:
    """One configuration of n blocks.

    Attributes:
        support: ``support[i]`` is what block ``i`` stands on: :data:`TABLE`,
            :data:`HAND`, or the index of the block beneath it.

    """

    support: tuple[int, ...]

    def __post_init__(self) -> None:
        _validate_support(self.support)

    @property
    def n(self) -> int:
        """Number of blocks."""
        return len(self.support)

    @property
    def held(self) -> int | None:
        """Index of the held block, or None when the hand is empty."""
        for i, s in enumerate(self.support):
            if s == HAND:
                return i
        return None

    def above(self, i: int) -> int | None:
        """The block standing directly on block ``i``, or None."""
        for j, s in enumerate(self.support):
            if s == i:
                return j
        return None

    def is_clear(self, i: int) -> bool:
        """True when nothing stands on block ``i`` and it is not held (the paper's clear)."""
        return self.support[i] != HAND and self.above(i) is None

    def towers(self) -> tuple[tuple[int, ...], ...]:
        """Towers bottom-up, sorted by their bottom block."""
        out = []
        for i, s in enumerate(self.support):
            if s == TABLE:
                tower = [i]
                while (top := self.above(tower[-1])) is not None:
                    tower.append(top)
                out.append(tuple(tower))
        return tuple(sorted(out))

    def notation(self) -> str:
        """The canonical configuration notation, e.g. ``A,CB+...``."""
        return format_config(self)

    def __str__(self) -> str:
        return self.notation()


def _validate_support(support: tuple[int, ...]) -> None:
    n = len(support)
    if not MIN_BLOCKS <= n <= MAX_BLOCKS:
        raise WorldError(f"number of blocks must be {MIN_BLOCKS}..{MAX_BLOCKS}, got {n}")
    if sum(1 for s in support if s == HAND) > 1:
        raise WorldError("more than one block is held")
    seen_under: set[int] = set()
    for i, s in enumerate(support):
        if s in (TABLE, HAND):
            continue
        if not 0 <= s < n or s == i:
            raise WorldError(f"block {block_name(i)} stands on an invalid support {s}")
        if s in seen_under:
            raise WorldError(f"two blocks stand on block {block_name(s)}")
        if support[s] == HAND:
            raise WorldError(f"block {block_name(i)} stands on the held block")
        seen_under.add(s)
    for i in range(n):
        j, steps = i, 0
        while support[j] >= 0:
            j = support[j]
            steps += 1
            if steps > n:
                raise WorldError("the blocks form a cycle")


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

    def name(self) -> str:
        """``pickup(A)``, ``putdown(A)``, ``unstack(A,B)`` or ``stack(A,B)``."""
        if self.target is None:
            return f"{self.kind.value}({block_name(self.block)})"
        return f"{self.kind.value}({block_name(self.block)},{block_name(self.target)})"

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
    return State(tuple(support))


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
    """The legal actions of ``state`` in the stable action order."""
    return tuple(a for a in all_actions(state.n) if is_legal(state, a))


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


# ---------------------------------------------------------------- notation


def format_config(state: State) -> str:
    """Canonical notation: towers bottom-up sorted and comma-joined, ``+X`` if holding X."""
    towers = ",".join("".join(block_name(i) for i in t) for t in sorted(
        state.towers(), key=lambda t: block_name(t[0])))
    held = state.held
    return towers + (f"+{block_name(held)}" if held is not None else "")
