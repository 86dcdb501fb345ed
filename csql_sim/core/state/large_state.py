"""Relational states of up to 26 blocks (A-Z), without enumerating the world.

:class:`LargeState` is the immutable relation ``on`` (with the table and the gripper as
supports, at most one block held), for 2..26 blocks. It reads and writes the same
configuration notation as :mod:`csql_sim.core.state.notation` (``CBA``, ``A,B,C``, ``B,C+A``), with
all 26 letters. The four STRIPS operators act on it exactly as on
:class:`csql_sim.core.state.world.State` (:func:`legal_actions`, :func:`successor`); actions are
:class:`csql_sim.core.state.world.Action` records, named by :func:`action_name`.

Counting and uniform sampling (:mod:`csql_sim.core.state.state_count`) and the message form for
n > 6 (:mod:`csql_sim.core.state.large_message`) build on it.
"""

from __future__ import annotations

import functools
import string
from dataclasses import dataclass

from csql_sim.core.state.world import HAND, MIN_BLOCKS, TABLE, Action, ActionKind, State, WorldError

LETTERS = string.ascii_uppercase
MAX_LARGE = len(LETTERS)
"""The most blocks a relational state holds: one per letter A-Z."""


def check_large_n(n: int) -> int:
    """Return ``n`` if it is 2..26, else raise WorldError."""
    if not isinstance(n, int) or isinstance(n, bool) or not MIN_BLOCKS <= n <= MAX_LARGE:
        raise WorldError(f"number of blocks must be {MIN_BLOCKS}..{MAX_LARGE}, got {n!r}")
    return n


@dataclass(frozen=True)
class LargeState:
    """One configuration of n <= 26 blocks: ``support[i]`` is TABLE, HAND or the block under i."""

    support: tuple[int, ...]

    def __post_init__(self) -> None:
        _validate(self.support)

    @property
    def n(self) -> int:
        """Number of blocks."""
        return len(self.support)

    @functools.cached_property
    def above_of(self) -> tuple[int | None, ...]:
        """``above_of[i]``: the block standing directly on block i, or None."""
        out: list[int | None] = [None] * self.n
        for j, s in enumerate(self.support):
            if s >= 0:
                out[s] = j
        return tuple(out)

    @property
    def held(self) -> int | None:
        """The held block, or None when the hand is empty."""
        return self.support.index(HAND) if HAND in self.support else None

    def is_clear(self, i: int) -> bool:
        """Nothing on block i and it is not held (the paper's clear)."""
        return self.support[i] != HAND and self.above_of[i] is None

    def clear(self) -> tuple[bool, ...]:
        """:meth:`is_clear` of every block."""
        return tuple(self.is_clear(i) for i in range(self.n))

    def towers(self) -> tuple[tuple[int, ...], ...]:
        """Towers bottom-up, sorted by their bottom block."""
        out = []
        for i, s in enumerate(self.support):
            if s == TABLE:
                tower = [i]
                while (top := self.above_of[tower[-1]]) is not None:
                    tower.append(top)
                out.append(tuple(tower))
        return tuple(out)

    def notation(self) -> str:
        """Canonical notation: towers bottom-up, sorted by bottom block, ``+X`` when holding X."""
        held = self.held
        text = ",".join("".join(LETTERS[i] for i in t) for t in self.towers())
        return text + (f"+{LETTERS[held]}" if held is not None else "")

    def __str__(self) -> str:
        return self.notation()

    @classmethod
    def from_state(cls, state: State) -> LargeState:
        """The relational form of a state of the enumerated world (n <= 6)."""
        return cls(state.support)

    def to_state(self) -> State:
        """The enumerated world's state (n <= 6 only)."""
        return State(self.support)


def _validate(support: tuple[int, ...]) -> None:
    n = len(support)
    if n < MIN_BLOCKS:  # any n from supports; the letter notation alone is capped at 26 (check_large_n)
        raise WorldError(f"number of blocks must be at least {MIN_BLOCKS}, got {n}")
    if support.count(HAND) > 1:
        raise WorldError("more than one block is held")
    under: set[int] = set()
    for i, s in enumerate(support):
        if s in (TABLE, HAND):
            continue
        if not isinstance(s, int) or not 0 <= s < n or s == i:
            raise WorldError(f"block {LETTERS[i]} stands on an invalid support {s!r}")
        if s in under:
            raise WorldError(f"two blocks stand on block {LETTERS[s]}")
        if support[s] == HAND:
            raise WorldError(f"block {LETTERS[i]} stands on the held block")
        under.add(s)
    for i in range(n):
        j, steps = i, 0
        while support[j] >= 0:
            j, steps = support[j], steps + 1
            if steps > n:
                raise WorldError("the blocks form a cycle")


def parse_large(text: str, n: int | None = None) -> LargeState:
    """Read the configuration notation with blocks A-Z (towers bottom-up, ``,`` between, ``+X`` held).

    Raises:
        WorldError: naming the unknown, repeated or missing block.
    """
    raw = text.replace(" ", "").upper()
    towers_part, plus, held_part = raw.partition("+")
    if not raw or "+" in held_part or (plus and len(held_part) != 1):
        raise WorldError(f"configuration {text!r}: expected towers such as CBA,D and at most one '+X'")
    towers = towers_part.split(",") if towers_part else []
    if any(not t for t in towers):
        raise WorldError(f"configuration {text!r} has an empty tower")
    letters = "".join(towers) + held_part
    for ch in letters:
        if ch not in LETTERS:
            raise WorldError(f"unknown block {ch!r} in configuration {text!r}")
        if letters.count(ch) > 1:
            raise WorldError(f"block {ch} is used twice in configuration {text!r}")
    n = check_large_n(len(letters) if n is None else n)
    missing = sorted(set(LETTERS[:n]) - set(letters))
    extra = sorted(set(letters) - set(LETTERS[:n]))
    if extra or missing:
        raise WorldError(f"unknown block {extra[0]} for a {n}-block world in {text!r}" if extra
                         else f"block {missing[0]} is missing from configuration {text!r}")
    support = [TABLE] * n
    for tower in towers:
        for below, top in zip(tower, tower[1:], strict=False):
            support[LETTERS.index(top)] = LETTERS.index(below)
    if held_part:
        support[LETTERS.index(held_part)] = HAND
    return LargeState(tuple(support))


# ---------------------------------------------------------------- actions


def action_name(action: Action) -> str:
    """``pickup(A)``, ``unstack(Z,Y)``: the tool's action names, with all 26 letters."""
    if action.target is None:
        return f"{action.kind.value}({LETTERS[action.block]})"
    return f"{action.kind.value}({LETTERS[action.block]},{LETTERS[action.target]})"


def action_count(n: int) -> int:
    """Number of actions of the n-block world: unstack and stack for each ordered pair, pickup and putdown."""
    return 2 * n * (n - 1) + 2 * n


def action_index(action: Action, n: int) -> int:
    """The action's index in the stable order of :func:`csql_sim.core.state.world.all_actions`, by arithmetic."""
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


def is_legal(state: LargeState, action: Action) -> bool:
    """STRIPS preconditions, as :func:`csql_sim.core.state.world.is_legal` states them."""
    b, kind = action.block, action.kind
    if kind is ActionKind.PUTDOWN:
        return state.held == b
    if kind is ActionKind.STACK:
        return state.held == b and action.target != b and state.is_clear(action.target)
    want = TABLE if kind is ActionKind.PICKUP else action.target
    return state.held is None and state.is_clear(b) and state.support[b] == want


def legal_actions(state: LargeState) -> tuple[Action, ...]:
    """The legal actions in the stable action order (without listing all actions)."""
    held = state.held
    if held is not None:
        onto = [Action(ActionKind.STACK, held, y) for y in range(state.n) if y != held and state.is_clear(y)]
        return (Action(ActionKind.PUTDOWN, held), *onto)
    ups = [Action(ActionKind.UNSTACK, x, s) for x, s in enumerate(state.support) if s >= 0 and state.is_clear(x)]
    picks = [Action(ActionKind.PICKUP, x) for x, s in enumerate(state.support) if s == TABLE and state.is_clear(x)]
    return (*ups, *picks)


def successor(state: LargeState, action: Action) -> LargeState:
    """The state after ``action``; raises WorldError if it is not legal."""
    if not is_legal(state, action):
        raise WorldError(f"{action_name(action)} is not legal in {state.notation()}")
    support = list(state.support)
    if action.kind in (ActionKind.PICKUP, ActionKind.UNSTACK):
        support[action.block] = HAND
    elif action.kind is ActionKind.PUTDOWN:
        support[action.block] = TABLE
    else:
        support[action.block] = action.target
    return LargeState(tuple(support))
