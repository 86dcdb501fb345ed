"""The configuration notation users type: reading states and action names.

* towers are separated by commas, each written from the bottom up: ``CBA`` is A on B on C;
  ``A,B,C`` is all three blocks on the table;
* a held block goes after ``+``: ``B,C+A`` (A in the gripper);
* case-insensitive; spaces are ignored; blocks A-Z, so up to 26 blocks.

:func:`csql_sim.core.state.world.format_config` writes the canonical form.
"""

from __future__ import annotations

from csql_sim.core.state.message import is_state_message, parse_state_message
from csql_sim.core.state.relational_message import is_relational_message, parse_large_message
from csql_sim.core.state.state import check_letters_n
from csql_sim.core.state.world import HAND, LETTERS, TABLE, Action, ActionKind, State, WorldError


def parse_config(text: str, n: int | None = None) -> State:
    """Parse the configuration notation (see the module docstring).

    Args:
        text: e.g. ``"CBA"``, ``"A,B,C"``, ``"b,c+a"``.
        n: expected number of blocks; inferred from the text when None.

    Raises:
        WorldError: naming the unknown, repeated or missing block.

    """
    raw = text.replace(" ", "").upper()
    if not raw:
        raise WorldError("empty configuration")
    if raw.count("+") > 1:
        raise WorldError(f"configuration {text!r} holds more than one block ('+' twice)")
    towers_part, _, held_part = raw.partition("+")
    if "+" in raw and len(held_part) != 1:
        raise WorldError(f"configuration {text!r}: exactly one block may follow '+'")
    towers = [t for t in towers_part.split(",")] if towers_part else []
    if any(not t for t in towers):
        raise WorldError(f"configuration {text!r} has an empty tower")
    letters = "".join(towers) + held_part
    for ch in letters:
        if ch not in LETTERS:
            raise WorldError(f"unknown block {ch!r} in configuration {text!r}")
    for ch in letters:
        if letters.count(ch) > 1:
            raise WorldError(f"block {ch} is used twice in configuration {text!r}")
    count = len(letters)
    if n is None:
        n = count
    check_letters_n(n)
    expected = set(LETTERS[:n])
    missing = sorted(expected - set(letters))
    extra = sorted(set(letters) - expected)
    if extra:
        raise WorldError(f"unknown block {extra[0]} for a {n}-block world in {text!r}")
    if missing:
        raise WorldError(f"block {missing[0]} is missing from configuration {text!r}")
    support = [TABLE] * n
    for tower in towers:
        for below, above in zip(tower, tower[1:], strict=False):
            support[LETTERS.index(above)] = LETTERS.index(below)
    if held_part:
        support[LETTERS.index(held_part)] = HAND
    return State(tuple(support))


def parse_action_name(text: str, n: int) -> Action:
    """Parse ``pickup(A)``, ``putdown(A)``, ``unstack(A,B)`` or ``stack(A,B)``."""
    raw = text.replace(" ", "").lower()
    head, sep, rest = raw.partition("(")
    if not sep or not rest.endswith(")"):
        raise WorldError(f"malformed action {text!r}; expected e.g. pickup(A) or stack(A,B)")
    try:
        kind = ActionKind(head)
    except ValueError:
        raise WorldError(f"unknown action {head!r} in {text!r}") from None
    args = [a.upper() for a in rest[:-1].split(",")]
    want = 2 if kind in (ActionKind.STACK, ActionKind.UNSTACK) else 1
    if len(args) != want:
        raise WorldError(f"{kind.value} takes {want} block(s), got {text!r}")
    for a in args:
        if len(a) != 1 or a not in LETTERS[:n]:
            raise WorldError(f"unknown block {a!r} in action {text!r}")
    idx = [LETTERS.index(a) for a in args]
    if want == 2 and idx[0] == idx[1]:
        raise WorldError(f"action {text!r} names block {args[0]} twice")
    return Action(kind, idx[0], idx[1] if want == 2 else None)


def parse_state_arg(text: str, n: int | None = None) -> State:
    """A user's state: the configuration notation, the paper's state message (n <= 6) or a relational one (7..26)."""
    text = text.strip()
    if is_relational_message(text):
        return parse_large_message(text, n).state
    if is_state_message(text):
        parsed = parse_state_message(text, n)
        return parsed.state
    return parse_config(text, n)
