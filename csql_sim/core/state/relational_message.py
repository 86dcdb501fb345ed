"""The message form for 7..26 blocks: the paper's fields, the goal written out, no letter ambiguity.

For n <= 6 the paper's form (:mod:`csql_sim.core.state.message`) stays as it is. Past six blocks
the paper's table symbol ``t`` is also block T, and a goal index would need 20 base-36
digits at n = 26, so the large form is (n block fields wide, no padding)::

    S  k..k   c..c     o..o     h   g..g     j
       code   clear    on       hand goal-on goal-hand

* ``S`` tag; ``k..k`` the action slot, as many base-36 digits as the largest action code
  (2 for n = 7..25, 3 for n = 26); ``0`` none.
* clear field, n characters: ``1`` clear, ``0`` not.
* on field, n characters: ``a``-``z`` the block it stands on, ``_`` the table, ``0`` held.
* hand: ``0`` empty, else the held block ``a``-``z``.
* the goal as a configuration: its on field (n characters, same alphabet) and its hand.

Neither table (``_``) nor held (``0``) is a letter. Length ``3n + 3 + width``: 26 at n = 7,
84 at n = 26; every n has its own length, none equal to a paper-form length (16-19).

Action message: ``A``, the action code, ``000000``, the motion flag ``1000`` (pick up) or
``0100`` (put down), the block moved, the block or table (``_``) it comes from or goes onto,
``00``, as in the paper's form. Action codes follow the stable action order (index + 1).
"""

from __future__ import annotations

from dataclasses import dataclass

from csql_sim.core.state.message import (
    DIGITS,
    PICK_FLAG,
    PUT_FLAG,
    MessageError,
    decode_code,
    encode_code,
    is_state_message,
)
from csql_sim.core.state.state import MAX_LETTERS, check_letters_n
from csql_sim.core.state.world import (
    HAND,
    LETTERS,
    MAX_BLOCKS,
    TABLE,
    Action,
    State,
    WorldError,
    action_at,
    action_count,
    action_index,
)

MIN_LARGE_MESSAGE = MAX_BLOCKS + 1
MAX_LARGE_MESSAGE = MAX_LETTERS
"""The relational message is the view of 7..26 blocks (one letter per block); past 26 there is none."""
TABLE_CHAR = "_"
HELD_CHAR = "0"


def code_width(n: int) -> int:
    """Base-36 digits of the largest action code of n blocks."""
    width = 1
    while len(DIGITS) ** width <= action_count(n):
        width += 1
    return width


def _check(n: int) -> int:
    check_letters_n(n)
    if n < MIN_LARGE_MESSAGE:
        raise MessageError(f"the large message form is for {MIN_LARGE_MESSAGE}..26 blocks, got {n} "
                           f"(use the paper's form for n <= {MAX_BLOCKS})")
    return n


def is_relational_message(text: str) -> bool:
    """A cheap test: a state message as long as the relational form's shortest, or longer (the paper's are shorter)."""
    return is_state_message(text) and len(text) >= message_length(MIN_LARGE_MESSAGE)


def message_length(n: int) -> int:
    """Length of a large state message for n blocks."""
    return 3 * _check(n) + 3 + code_width(n)


def _on(support: int) -> str:
    return TABLE_CHAR if support == TABLE else HELD_CHAR if support == HAND else LETTERS[support].lower()


def _hand(state: State) -> str:
    return HELD_CHAR if state.held is None else LETTERS[state.held].lower()


def format_large_message(state: State, goal: State, action: Action | None = None) -> str:
    """The large state message of ``state`` towards ``goal`` (action slot: ``action``'s code, or 0)."""
    n = _check(state.n)
    if goal.n != n:
        raise WorldError(f"start has {n} blocks but goal has {goal.n}")
    code = 0 if action is None else action_index(action, n) + 1
    clear = "".join("1" if state.is_clear(i) else "0" for i in range(n))
    return ("S" + encode_code(code, code_width(n)) + clear + "".join(map(_on, state.support)) + _hand(state)
            + "".join(map(_on, goal.support)) + _hand(goal))


@dataclass(frozen=True)
class LargeMessage:
    """A parsed large state message: the state, the goal and the action slot (None: 0)."""

    state: State
    goal: State
    action: Action | None


def _fail(message: str, pos: int, expected: str) -> MessageError:
    return MessageError(f"malformed message {message!r}: position {pos} is {message[pos]!r}, expected {expected}")


def infer_large_blocks(message: str) -> int:
    """The number of blocks of a large message, from its length."""
    for n in range(MIN_LARGE_MESSAGE, len(LETTERS) + 1):
        if message_length(n) == len(message):
            return n
    raise MessageError(f"message {message!r} has {len(message)} characters, the length of no 7..26-block "
                       f"large message ({message_length(MIN_LARGE_MESSAGE)}..{message_length(len(LETTERS))})")


def _supports(message: str, start: int, n: int) -> list[int]:
    out = []
    for i in range(n):
        ch = message[start + i]
        if ch == TABLE_CHAR:
            out.append(TABLE)
        elif ch == HELD_CHAR:
            out.append(HAND)
        elif ch in LETTERS[:n].lower() and ch != LETTERS[i].lower():
            out.append(LETTERS.index(ch.upper()))
        else:
            raise _fail(message, start + i, f"_, 0 or another of a..{LETTERS[n - 1].lower()}")
    return out


def _configuration(message: str, on: int, n: int) -> State:
    supports = tuple(_supports(message, on, n))  # its MessageError (a WorldError) names the message already
    try:
        state = State(supports)
    except WorldError as exc:
        raise MessageError(f"malformed message {message!r}: {exc}") from None
    if message[on + n] != _hand(state):
        raise _fail(message, on + n, f"{_hand(state)!r} (agreeing with the on field)")
    return state


def parse_large_message(message: str, n: int | None = None) -> LargeMessage:
    """Inverse of :func:`format_large_message`; checks every field against the others.

    Raises:
        MessageError: naming the first bad position and its character.
    """
    n = infer_large_blocks(message) if n is None else _check(n)
    if len(message) != message_length(n):
        raise MessageError(f"malformed message {message!r}: {len(message)} characters, "
                           f"expected {message_length(n)} for n={n}")
    if message[0] != "S":
        raise _fail(message, 0, "'S'")
    w = code_width(n)
    slot = message[1 : 1 + w]
    if any(ch.upper() not in DIGITS for ch in slot) or decode_code(slot) > action_count(n):
        raise _fail(message, 1, f"an action code 0..{encode_code(action_count(n), w)}")
    code = decode_code(slot)
    clear_at = 1 + w
    state = _configuration(message, clear_at + n, n)
    goal = _configuration(message, clear_at + 2 * n + 1, n)
    for i in range(n):
        want = "1" if state.is_clear(i) else "0"
        if message[clear_at + i] != want:
            raise _fail(message, clear_at + i, f"{want!r} (agreeing with the on field)")
    return LargeMessage(state, goal, None if code == 0 else action_at(code - 1, n))


def format_large_action(action: Action, n: int) -> str:
    """The large action message of ``action`` in the n-block world."""
    _check(n)
    flag = PICK_FLAG if action.is_pick else PUT_FLAG
    where = TABLE_CHAR if action.target is None else LETTERS[action.target].lower()
    code = encode_code(action_index(action, n) + 1, code_width(n))
    return "A" + code + "000000" + flag + LETTERS[action.block].lower() + where + "00"


def parse_large_action(message: str, n: int) -> Action:
    """Inverse of :func:`format_large_action` (the code must agree with the motion and the blocks)."""
    w = code_width(_check(n))
    slot = message[1 : 1 + w]
    if not message.startswith("A") or any(ch.upper() not in DIGITS for ch in slot) \
            or not 1 <= decode_code(slot) <= action_count(n):
        raise MessageError(f"malformed action message {message!r}: expected 'A' and an action code "
                           f"1..{encode_code(action_count(n), w)}")
    action = action_at(decode_code(slot) - 1, n)
    expected = format_large_action(action, n)
    if message != expected:
        raise MessageError(f"malformed action message {message!r}: expected {expected!r} for code {slot}")
    return action
