"""The paper's state and action messages, exact for n=3 and widened for n up to 6.

State message layout (positions for n=3; see docs/encoding.md)::

    S  k  cccccc  oooooo  h  g
    0  1  2..7    8..13   14 15

* ``S`` tag.
* ``k`` action slot, ``action_width`` characters: ``0`` none, else the code of the action
  just taken (read by the add-delete rules).
* ``cccccc`` clear field, one slot per block A..F: ``1`` clear (nothing on top and not
  held), ``0`` not clear. Slots of blocks beyond n are ``0``.
* ``oooooo`` on field, one slot per block A..F: ``t`` table, ``a``..``f`` a block, ``0``
  held. Slots of blocks beyond n are ``0``.
* ``h`` the held block ``a``..``f``, or ``0``.
* ``g`` the goal's state index (:func:`csql_sim.core.state.world.all_states` order), ``goal_width``
  characters in base 36 (``0``-``9`` then ``A``-``Z``).

The block fields are six wide for every n (the paper's three unused ``0`` are the room for
blocks D..F); the action slot and goal code widen to as many base-36 digits as their
largest value needs. Lengths: n=2 and n=3: 16; n=4: 17; n=5: 18; n=6: 19.

Action message: ``A``, the action code (``action_width``), ``000000``, a motion flag
``1000`` (pick up) or ``0100`` (put down), the block moved, the block or table (``t``) it
comes from or goes onto, ``00``. E.g. ``A10000001000ab00`` is unstack(A,B).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

from csql_sim.core.state.world import (
    BLOCK_NAMES,
    HAND,
    MAX_BLOCKS,
    TABLE,
    Action,
    ActionKind,
    State,
    WorldError,
    all_actions,
    all_states,
    check_n,
)

DIGITS = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ"
BLOCK_FIELD = MAX_BLOCKS
PICK_FLAG = "1000"
PUT_FLAG = "0100"


class MessageError(WorldError):
    """A malformed message; the text names the position and the character."""


def _digits_needed(largest: int) -> int:
    width = 1
    while len(DIGITS) ** width <= largest:
        width += 1
    return width


def encode_code(value: int, width: int) -> str:
    """``value`` in base 36, zero-padded to ``width`` characters."""
    out = ""
    for _ in range(width):
        value, r = divmod(value, len(DIGITS))
        out = DIGITS[r] + out
    if value:
        raise ValueError(f"{value} does not fit in {width} base-36 digits")
    return out


def decode_code(text: str) -> int:
    """Inverse of :func:`encode_code` (case-insensitive)."""
    value = 0
    for ch in text.upper():
        value = value * len(DIGITS) + DIGITS.index(ch)
    return value


@dataclass(frozen=True)
class MessageLayout:
    """Field positions of the n-block messages.

    Attributes:
        n: number of blocks.
        action_width: characters of the action code (1 for n <= 4).
        goal_width: characters of the goal code (1 for n <= 3).

    """

    n: int
    action_width: int
    goal_width: int

    @property
    def clear_start(self) -> int:
        return 1 + self.action_width

    @property
    def on_start(self) -> int:
        return self.clear_start + BLOCK_FIELD

    @property
    def held_pos(self) -> int:
        return self.on_start + BLOCK_FIELD

    @property
    def goal_start(self) -> int:
        return self.held_pos + 1

    @property
    def length(self) -> int:
        """Length of both the state and the action message."""
        return self.goal_start + self.goal_width

    def action_slot(self, message: str) -> str:
        """The action-slot characters of a state message."""
        return message[1 : 1 + self.action_width]


@functools.cache
def layout(n: int) -> MessageLayout:
    """The message layout for n blocks."""
    check_n(n)
    lay = MessageLayout(
        n=n,
        action_width=_digits_needed(len(all_actions(n))),
        goal_width=_digits_needed(len(all_states(n)) - 1),
    )
    # The action message (A, code, 6 zeros, 4 flags, block, from/onto, 2 zeros) has
    # 1 + action_width + 14 characters; pad its tail so both messages share one length.
    return lay


def _on_char(support: int) -> str:
    if support == TABLE:
        return "t"
    if support == HAND:
        return "0"
    return BLOCK_NAMES[support].lower()


def format_state_message(state: State, goal: int, action_code: int = 0) -> str:
    """The state message of ``state`` with goal index ``goal``.

    Args:
        state: the configuration.
        goal: the goal state's index in :func:`all_states` order.
        action_code: the action slot (0 for none, else action index + 1).

    """
    lay = layout(state.n)
    if not 0 <= goal < len(all_states(state.n)):
        raise WorldError(f"goal index {goal} out of range for n={state.n}")
    clear = "".join("1" if state.is_clear(i) else "0" for i in range(state.n))
    on = "".join(_on_char(s) for s in state.support)
    held = state.held
    return (
        "S"
        + encode_code(action_code, lay.action_width)
        + clear.ljust(BLOCK_FIELD, "0")
        + on.ljust(BLOCK_FIELD, "0")
        + (BLOCK_NAMES[held].lower() if held is not None else "0")
        + encode_code(goal, lay.goal_width)
    )


@dataclass(frozen=True)
class StateMessage:
    """A parsed state message.

    Attributes:
        state: the configuration it describes.
        goal: the goal's state index.
        action_code: the action slot (0 for none).

    """

    state: State
    goal: int
    action_code: int


def _fail(message: str, pos: int, expected: str) -> MessageError:
    ch = message[pos] if pos < len(message) else "end of message"
    shown = repr(ch) if pos < len(message) else ch
    return MessageError(f"malformed message {message!r}: position {pos} is {shown}, expected {expected}")


def infer_blocks(message: str) -> int:
    """The number of blocks a state message describes, read from its on and held fields."""
    if not message or message[0] != "S":
        raise _fail(message, 0, "'S'")
    lengths: dict[int, list[str]] = {}
    for n in range(MIN_OK, MAX_BLOCKS + 1):
        lengths.setdefault(layout(n).length, []).append(str(n))
    if len(message) not in lengths:
        sizes = ", ".join(f"{length} ({' or '.join(ns)} blocks)" for length, ns in sorted(lengths.items()))
        short = "too short" if len(message) < min(lengths) else "of no block count's length"
        raise MessageError(f"state message {message!r} is {short}: {len(message)} characters; "
                           f"a state message has {sizes}")
    for width in (1, 2):
        on_start = 1 + width + BLOCK_FIELD
        on = message[on_start : on_start + BLOCK_FIELD]
        held = message[on_start + BLOCK_FIELD]
        n = sum(1 for ch in on if ch != "0") + (held != "0")
        if MIN_OK <= n <= MAX_BLOCKS and layout(n).action_width == width and len(message) == layout(n).length:
            return n
    raise MessageError(f"malformed message {message!r}: its length and fields fit no 2..6-block layout")


MIN_OK = 2


def parse_state_message(message: str, n: int | None = None) -> StateMessage:
    """Parse a state message; the inverse of :func:`format_state_message`.

    Args:
        message: e.g. ``S0111000ttt0000C``.
        n: number of blocks; inferred from the message when None.

    Raises:
        MessageError: naming the first bad position and its character.

    """
    if n is None:
        n = infer_blocks(message)
    lay = layout(n)
    if len(message) != lay.length:
        raise MessageError(
            f"malformed message {message!r}: {len(message)} characters, expected {lay.length} for n={n}"
        )
    if message[0] != "S":
        raise _fail(message, 0, "'S'")
    action_code = _parse_action_slot(message, lay)
    support = _parse_on_field(message, lay)
    goal = _parse_goal(message, lay)
    try:
        state = State(tuple(support))
    except WorldError as exc:
        raise MessageError(f"malformed message {message!r}: {exc}") from None
    _check_clear_and_held(message, lay, state)
    return StateMessage(state=state, goal=goal, action_code=action_code)


def _base36(message: str, start: int, text: str) -> int:
    for k, ch in enumerate(text):
        if not ch.isascii() or ch.upper() not in DIGITS:
            raise _fail(message, start + k, "a base-36 digit")
    return decode_code(text)


def _parse_action_slot(message: str, lay: MessageLayout) -> int:
    """The action code in the slot (0: none), within the world's actions."""
    code = _base36(message, 1, lay.action_slot(message))
    count = len(all_actions(lay.n))
    if code > count:
        raise _fail(message, 1, f"an action code 0..{encode_code(count, lay.action_width)}")
    return code


def _supports(message: str, start: int, n: int) -> list[int]:
    """What each block stands on, from an on field of :data:`BLOCK_FIELD` characters at ``start``.

    Used for the state's on field here and for the goal's in the goal form.
    """
    names = BLOCK_NAMES[:n].lower()
    support = []
    for i in range(BLOCK_FIELD):
        pos, ch = start + i, message[start + i]
        if i >= n:
            if ch != "0":
                raise _fail(message, pos, "'0' (no such block)")
        elif ch == "t":
            support.append(TABLE)
        elif ch == "0":
            support.append(HAND)
        elif ch in names and ch != names[i]:
            support.append(names.index(ch))
        else:
            raise _fail(message, pos, f"t, 0 or another of {names}")
    return support


def _parse_on_field(message: str, lay: MessageLayout) -> list[int]:
    """Each block's support from the on field; clear slots and unused slots checked for shape."""
    n, names = lay.n, BLOCK_NAMES[: lay.n].lower()
    for i in range(BLOCK_FIELD):
        pos = lay.clear_start + i
        allowed = "01" if i < n else "0"
        if message[pos] not in allowed:
            raise _fail(message, pos, " or ".join(allowed))
    support = _supports(message, lay.on_start, n)
    held_ch = message[lay.held_pos]
    if held_ch != "0" and held_ch not in names:
        raise _fail(message, lay.held_pos, f"0 or one of {names}")
    return support


def _parse_goal(message: str, lay: MessageLayout) -> int:
    goal = _base36(message, lay.goal_start, message[lay.goal_start :])
    count = len(all_states(lay.n))
    if goal >= count:
        raise _fail(message, lay.goal_start, f"a goal code below {count}")
    return goal


def _check_clear_and_held(message: str, lay: MessageLayout, state: State) -> None:
    """The clear and held fields must agree with the on field."""
    held = state.held
    want_held = BLOCK_NAMES[held].lower() if held is not None else "0"
    if message[lay.held_pos] != want_held:
        raise _fail(message, lay.held_pos, repr(want_held) + " (agreeing with the on field)")
    for i in range(state.n):
        want = "1" if state.is_clear(i) else "0"
        if message[lay.clear_start + i] != want:
            raise _fail(message, lay.clear_start + i, repr(want) + " (agreeing with the on field)")


def format_action_message(action: Action, n: int) -> str:
    """The action message of ``action`` in the n-block world."""
    lay = layout(n)
    code = all_actions(n).index(action) + 1
    flag = PICK_FLAG if action.is_pick else PUT_FLAG
    where = "t" if action.target is None else BLOCK_NAMES[action.target].lower()
    body = "A" + encode_code(code, lay.action_width) + "000000" + flag + BLOCK_NAMES[action.block].lower() + where
    return body.ljust(lay.length, "0")


def parse_action_message(message: str, n: int) -> Action:
    """Parse an action message; checks the code against the motion and blocks."""
    lay = layout(n)
    if len(message) != lay.length:
        raise MessageError(
            f"malformed action message {message!r}: {len(message)} characters, expected {lay.length}"
        )
    if message[0] != "A":
        raise _fail(message, 0, "'A'")
    slot = message[1 : 1 + lay.action_width]
    code = _base36(message, 1, slot)
    actions = all_actions(n)
    if not 1 <= code <= len(actions):
        raise _fail(message, 1, f"an action code 1..{encode_code(len(actions), lay.action_width)}")
    action = actions[code - 1]
    expected = format_action_message(action, n)
    for pos, (got, want) in enumerate(zip(message, expected, strict=True)):
        if got != want:
            raise _fail(message, pos, repr(want) + f" for action code {slot}")
    return action


@functools.cache
def action_messages(n: int) -> tuple[str, ...]:
    """Every action message of n blocks, in the stable action order (index = action code - 1)."""
    return tuple(format_action_message(a, n) for a in all_actions(n))


def action_code(action: Action, n: int) -> str:
    """The action's code character(s), e.g. ``7`` for pickup(A) when n=3."""
    return encode_code(all_actions(n).index(action) + 1, layout(n).action_width)


def goal_code(goal: int, n: int) -> str:
    """The goal index as it appears in a state message."""
    return encode_code(goal, layout(n).goal_width)


def is_state_message(text: str) -> bool:
    """A cheap test: does ``text`` look like a state message rather than a configuration?"""
    # a configuration holds no digit (block S may start one); every message holds its clear field's digits
    return len(text) >= 2 and text[0] == "S" and text[1].isalnum() and any(ch.isdigit() for ch in text)


__all__ = [
    "ActionKind",
    "MessageError",
    "MessageLayout",
    "StateMessage",
    "action_code",
    "format_action_message",
    "format_state_message",
    "goal_code",
    "infer_blocks",
    "is_state_message",
    "layout",
    "parse_action_message",
    "parse_state_message",
]
