"""The configuration notation users type: reading states and action names.

* towers are separated by commas, each written from the bottom up: ``CBA`` is A on B on C;
  ``A,B,C`` is all three blocks on the table;
* a held block goes after ``+``: ``B,C+A`` (A in the gripper);
* case-insensitive; blocks A-Z, one letter each (spaces are ignored), up to 26 blocks;
* past 26 blocks the names go on (``AA``, ``AB``, ...) and a tower's names are separated by
  spaces: ``C AA B, D + AB``.

:func:`csql_sim.core.state.world.format_config` writes the canonical form.
"""

from __future__ import annotations

import functools

from csql_sim.core.state.message import is_state_message, parse_state_message
from csql_sim.core.state.relational_message import is_relational_message, parse_large_message
from csql_sim.core.state.state import MIN_LETTERS, check_letters_n, default_names
from csql_sim.core.state.world import HAND, LETTERS, TABLE, Action, ActionKind, State, WorldError


def parse_config(text: str, n: int | None = None) -> State:
    """Parse the configuration notation (see the module docstring).

    Args:
        text: e.g. ``"CBA"``, ``"A,B,C"``, ``"b,c+a"``.
        n: expected number of blocks; inferred from the text when None.

    Raises:
        WorldError: naming the unknown, repeated or missing block.

    """
    towers, held = _tokens(text)
    names = [name for tower in towers for name in tower] + held
    for name in names:
        if names.count(name) > 1:
            raise WorldError(f"block {name} is used twice in configuration {text!r}")
    if n is None:
        n = len(names)
    if len(max(names, key=len)) == 1:
        check_letters_n(n)
    elif not isinstance(n, int) or n < MIN_LETTERS:
        raise WorldError(f"number of blocks must be at least {MIN_LETTERS}, got {n!r}")
    index = {name: i for i, name in enumerate(default_names(n))}
    extra = sorted(set(names) - set(index), key=lambda x: (len(x), x))
    missing = [name for name in index if name not in names]
    if extra:
        if all(name.isalpha() for name in extra) and len(extra[0]) <= 1 + len(default_names(n)[-1]):
            raise WorldError(f"unknown block {extra[0]} for a {n}-block world in {text!r}")
        raise WorldError(f"unknown block {extra[0]!r} in configuration {text!r}")
    if missing:
        raise WorldError(f"block {missing[0]} is missing from configuration {text!r}")
    support = [TABLE] * n
    for tower in towers:
        for below, above in zip(tower, tower[1:], strict=False):
            support[index[above]] = index[below]
    if held:
        support[index[held[0]]] = HAND
    return State(tuple(support))


def _tokens(text: str) -> tuple[list[list[str]], list[str]]:
    """The towers (bottom up) and the held block of a configuration, as block names.

    One letter per block (``CBA``), or, where a tower's names are separated by spaces
    (``C AA B``, the notation past 26 blocks) or there are more letters than 26, one name
    per word (``A, B, ..., AA``).
    """
    upper = text.upper()
    if not upper.replace(" ", ""):
        raise WorldError("empty configuration")
    if upper.count("+") > 1:
        raise WorldError(f"configuration {text!r} holds more than one block ('+' twice)")
    towers_part, _, held_part = upper.partition("+")
    chunks = towers_part.split(",") if towers_part.strip() else []
    letters = sum(ch.isalpha() for ch in upper)
    words = any(len(chunk.split()) > 1 for chunk in chunks) or letters > len(LETTERS)

    def split(chunk: str) -> list[str]:
        return chunk.split() if words else list(chunk.replace(" ", ""))

    towers = [split(chunk) for chunk in chunks]
    held = held_part.split() if words else list(held_part.replace(" ", ""))
    if "+" in upper and len(held) != 1:
        raise WorldError(f"configuration {text!r}: exactly one block may follow '+'")
    if any(not t for t in towers):
        raise WorldError(f"configuration {text!r} has an empty tower")
    for name in [x for t in towers for x in t] + held:
        if not name.isalpha() or not name.isascii():
            raise WorldError(f"unknown block {name!r} in configuration {text!r}")
    return towers, held


@functools.cache
def _name_index(n: int) -> dict[str, int]:
    """The default names of n blocks (``A`` .. ``Z``, ``AA``, ...) -> their indices."""
    return {name: i for i, name in enumerate(default_names(n))}


def parse_action_name(text: str, n: int) -> Action:
    """Parse ``pickup(A)``, ``putdown(A)``, ``unstack(A,B)`` or ``stack(A,B)`` (past Z: ``stack(AA,B)``)."""
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
    index = _name_index(n)
    for a in args:
        if a not in index:
            raise WorldError(f"unknown block {a!r} in action {text!r}")
    idx = [index[a] for a in args]
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
