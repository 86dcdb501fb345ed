"""Plans in the IPC format, as Fast Downward and pyperplan write them: read, check, write.

A plan file has one action per line, ``(unstack a b)``; everything after ``;`` is a
comment (Fast Downward ends its plans with ``; cost = 8 (unit cost)``); blank lines are
skipped; a leading step number ``3:`` and a trailing duration ``[1]`` are tolerated.
csql-sim's own action names (``unstack(A,B)``, cube letters) are accepted too.

Each line becomes one or two blocks-world actions (:class:`PlanStep`):

* ``pick-up x``, ``put-down x``, ``stack x y``, ``unstack x y`` (also ``pickup``, ``putdown``): one;
* ``move-b-to-b x from to``: unstack(x, from), stack(x, to); ``move-b-to-t x from`` (alias
  ``move-to-t``, ``move-to-table``): unstack(x, from), putdown(x); ``move-t-to-b x to``:
  pickup(x), stack(x, to); ``move x from to`` with ``table`` for the table: a pick from
  ``from`` and a put onto ``to``;
* csql-sim's export (``csql-sim pddl``): ``unstack_a_b``, ``pickup_a``, ...: one.

:func:`check_plan` applies the steps to the start state and names the first step that is
not applicable, with its line number, before anything runs. :func:`write_ipc_plan` writes
actions back in the format (so plans round-trip between csql-sim and outside planners and
validators).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from csql_sim.core.state.notation import parse_action_name
from csql_sim.core.state.state import default_name
from csql_sim.core.state.world import (
    HAND,
    TABLE,
    Action,
    ActionKind,
    Precondition,
    State,
    WorldError,
    action_name,
    is_legal,
    preconditions,
    successor,
)
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import read_text_file, write_atomic

MAX_PLAN_BYTES = 1 << 20
"""The largest plan file read (1 MiB)."""
_IPC = re.compile(r"^(?:\d+(?:\.\d+)?\s*:\s*)?\(\s*([^()\s]+)((?:\s+[^()\s]+)*)\s*\)\s*(?:\[[^\]]*\])?$")
_CSQL_EXPORT = re.compile(r"^(unstack|stack|pickup|putdown)_([a-f])(?:_([a-f]))?$")
_SINGLE = {"pick-up": ActionKind.PICKUP, "pickup": ActionKind.PICKUP, "pick_up": ActionKind.PICKUP,
           "put-down": ActionKind.PUTDOWN, "putdown": ActionKind.PUTDOWN, "put_down": ActionKind.PUTDOWN,
           "stack": ActionKind.STACK, "unstack": ActionKind.UNSTACK}
_MOVES = {"move-b-to-b": 3, "move-b-to-t": 2, "move-to-t": 2, "move-to-table": 2, "move_to_table": 2,
          "move-t-to-b": 2, "move": 3}


class PlanError(CsqlError):
    """A plan that cannot be read, or a step that is not applicable where it comes."""


@dataclass(frozen=True)
class PlanStep:
    """One line of a plan.

    Attributes:
        line: its line number in the plan file (for a list of actions: its position, from 1).
        text: the line as written (comment removed), e.g. ``(move-b-to-b a b c)``.
        actions: the blocks-world actions it stands for (two for a move).
    """

    line: int
    text: str
    actions: tuple[Action, ...]


def plan_index(names: Sequence[str]) -> dict[str, int]:
    """What a plan file may name: each block's name (lower case; PDDL names compare without case) and ``table``."""
    return {**{name.lower(): i for i, name in enumerate(names)}, "table": TABLE}


def parse_plan(lines: Iterable[str], index: Mapping[str, int], n: int, source: str = "plan",
               allowed: Iterable[str] | None = None) -> list[PlanStep]:
    """Parse plan lines (see the module docstring).

    Args:
        lines: the plan's lines, in order (line numbers count from 1).
        index: PDDL object name (lower case) -> block index, ``table`` -> TABLE.
        n: number of blocks (for csql-sim's action names).
        source: the plan's name in messages.
        allowed: the domain's action names; an IPC action outside them is refused.

    Raises:
        PlanError: naming the line that cannot be read.
    """
    allowed = None if allowed is None else set(allowed)
    steps = []
    for number, raw in enumerate(lines, start=1):
        text = raw.split(";", 1)[0].strip()
        if text:
            steps.append(PlanStep(number, text, _actions(text, index, n, f"{source} line {number}", allowed)))
    return steps


def read_plan(path: str | os.PathLike, index: Mapping[str, int], n: int,
              allowed: Iterable[str] | None = None) -> list[PlanStep]:
    """Read and parse a plan file (UTF-8, at most :data:`MAX_PLAN_BYTES`)."""
    text = read_text_file(path, MAX_PLAN_BYTES, "plan file")
    return parse_plan(text.splitlines(), index, n, os.fspath(path), allowed)


def _actions(text: str, index: Mapping[str, int], n: int, where: str, allowed: set[str] | None) -> tuple[Action, ...]:
    found = _IPC.match(text.lower())
    if found is None:
        try:
            return (parse_action_name(text, n),)
        except WorldError as exc:
            raise PlanError(f"{where}: {text!r} is not an action ({exc})") from None
    name, args = found.group(1), found.group(2).split()
    if allowed is not None and name not in allowed:
        raise PlanError(f"{where}: {name} is not an action of the domain ({', '.join(sorted(allowed))})")
    export = _CSQL_EXPORT.match(name)
    if export and not args:
        return (parse_action_name(_export_name(export), n),)
    ids = []
    for arg in args:
        if arg not in index:
            raise PlanError(f"{where}: unknown object {arg!r} in {text}")
        ids.append(index[arg])
    return _from_ipc(name, ids, where, text)


def _export_name(found: re.Match) -> str:
    kind, x, y = found.groups()
    return f"{kind}({x}{',' + y if y else ''})"


def _from_ipc(name: str, ids: list[int], where: str, text: str) -> tuple[Action, ...]:
    want = 2 if _SINGLE.get(name) in (ActionKind.STACK, ActionKind.UNSTACK) else 1 if name in _SINGLE else \
        _MOVES.get(name)
    if want is None:
        raise PlanError(f"{where}: unknown action {name!r} in {text} (blocks-world actions: pick-up, put-down, "
                        f"stack, unstack, or a move)")
    if len(ids) != want:
        raise PlanError(f"{where}: {name} takes {want} argument(s), got {text}")
    if ids[0] == TABLE or (name != "move" and TABLE in ids):
        raise PlanError(f"{where}: {text} names the table where a block is expected")
    if ids[0] in ids[1:]:
        raise PlanError(f"{where}: {text} moves a block from or onto itself")
    if name in _SINGLE:
        return (Action(_SINGLE[name], ids[0], ids[1] if want == 2 else None),)
    block, rest = ids[0], ids[1:]
    if name == "move-b-to-b":
        pick, put = rest
    elif name == "move-t-to-b":
        pick, put = TABLE, rest[0]
    elif name == "move":
        pick, put = rest
    else:
        pick, put = rest[0], TABLE
    first = Action(ActionKind.PICKUP, block) if pick == TABLE else Action(ActionKind.UNSTACK, block, pick)
    second = Action(ActionKind.PUTDOWN, block) if put == TABLE else Action(ActionKind.STACK, block, put)
    return first, second


def check_plan(start: State, steps: Sequence[PlanStep], names: Sequence[str] | None = None,
               source: str = "plan") -> list[State]:
    """Apply ``steps`` to ``start``; the states before each action, and the end state last.

    Any n: the STRIPS preconditions and effects act on the relational state
    (:func:`csql_sim.core.state.world.successor`).

    Raises:
        PlanError: ``<source> line L: step K <text> = <action> is not applicable in <state>: <why>``
            for the first action whose preconditions fail.
    """
    trace, state, k = [start], start, 0
    for step in steps:
        for action in step.actions:
            k += 1
            if not is_legal(state, action):
                raise PlanError(f"{source} line {step.line}: step {k} {step.text}{_part(step, action, state)} is "
                                f"not applicable in {state.named_notation()}: {_why(state, action, step, names)}")
            state = successor(state, action)
            trace.append(state)
    return trace


def _own(step: PlanStep, action: Action) -> bool:
    """Whether the step is written in cube letters (csql-sim's own action names)."""
    return step.text.replace(" ", "").lower() == action_name(action).lower()


def _part(step: PlanStep, action: Action, state: State) -> str:
    """What the message adds after the step's text: the failing half of a move, or its action in letters."""
    if _own(step, action) or (len(step.actions) == 1 and state.names is not None):
        return ""  # the step's text already names the action in the problem's words
    label = action.name(state.names)
    return f" = {label}" if len(step.actions) == 1 else f" (its {label})"


def _why(state: State, action: Action, step: PlanStep, names: Sequence[str] | None) -> str:
    """:func:`why_not` in the state's own names, else in ``names`` (a plan not in cube letters)."""
    return why_not(state, action, None if _own(step, action) or state.names is not None else names)


def why_not(state: State, action: Action, names: Sequence[str] | None = None) -> str:
    """The first precondition of ``action`` that ``state`` violates, in words."""

    def name(i: int | None) -> str:
        return "nothing" if i is None else (names[i] if names is not None else state.name(i))

    failed: Precondition = next(p for p in preconditions(action) if not p.holds(state))
    held = state.held
    if failed.what == "held":
        if failed.value is None:
            return f"the hand is not empty (it holds {name(held)})"
        return f"{name(failed.value)} is not held (the hand holds {name(held)})"
    b = failed.block
    if failed.what == "clear":
        if state.support[b] == HAND:
            return f"{name(b)} is held"
        return f"{name(b)} is not clear ({name(state.support.index(b))} is on it)"
    where = state.support[b]
    now = "in the hand" if where == HAND else "on the table" if where == TABLE else f"on {name(where)}"
    target = "the table" if failed.value == TABLE else name(failed.value)
    return f"{name(b)} is not on {target} (it is {now})"


def ipc_action(action: Action, names: Sequence[str] | None = None) -> str:
    """One action in IPC form, ``(unstack a b)`` (``names``: the blocks' PDDL names, default a, b, ...)."""
    word = {ActionKind.PICKUP: "pick-up", ActionKind.PUTDOWN: "put-down", ActionKind.STACK: "stack",
            ActionKind.UNSTACK: "unstack"}[action.kind]
    args = [action.block] + ([] if action.target is None else [action.target])
    return "(" + " ".join([word, *((names[i] if names else default_name(i).lower()) for i in args)]) + ")"


def ipc_plan_text(actions: Iterable[Action], names: Sequence[str] | None = None, header: str = "") -> str:
    """A plan file's text, as Fast Downward writes it: one action per line, then ``; cost = N (unit cost)``.

    ``header``: a comment line written first (e.g. ``; csql-sim plan ...``, which marks the
    file as the tool's own output); plan readers skip comments.
    """
    return ipc_lines_text([ipc_action(a, names) for a in actions], header)


def ipc_lines_text(lines: Sequence[str], header: str = "") -> str:
    """A plan file's text from its action lines (in any domain's words), with the cost line."""
    head = f"{header}\n" if header else ""
    return head + "".join(line + "\n" for line in lines) + f"; cost = {len(lines)} (unit cost)\n"


def write_ipc_plan_lines(lines: Sequence[str], path: str | os.PathLike, header: str = "") -> Path:
    """Write action lines (already in a domain's words) as an IPC plan file, atomically."""
    return write_atomic(path, ipc_lines_text(lines, header))


def write_ipc_plan(actions: Iterable[Action], path: str | os.PathLike, names: Sequence[str] | None = None,
                   header: str = "") -> Path:
    """Write ``actions`` as an IPC plan file (atomically); returns the path."""
    return write_atomic(path, ipc_plan_text(actions, names, header))
