"""Plans in a problem's own words: its object names and its domain's action names.

csql-sim plans in the four operators (pickup, putdown, stack, unstack). A plan file is
written in the vocabulary of the problem it solves (:func:`spelled_plan_lines`):

* ``4op``: ``pick-up``/``pickup`` and ``put-down``/``putdown`` as the domain spells them
  (IPC's hyphenated names without a domain), ``stack``, ``unstack``;
* ``move``: one move per pick and put, with the domain's operator and arity:
  ``move-b-to-b ?b ?from ?to``, ``move-b-to-t ?b ?from`` (or ``move-to-t``),
  ``move-t-to-b ?b ?to``; or ``move ?b ?from ?to`` with the table object's name (and
  ``move-to-table ?b ?from`` where the domain has it). Without a domain a problem that names
  a table object gets ``move``, else the ``move-b-to-*`` family;
* ``csql``: csql-sim's own export, ``(unstack_a_b)``, ``(pickup_a)``, ....

:func:`csql_sim.core.files.ipc_plan.parse_plan` reads every one of these back.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from csql_sim.core.files.ipc_plan import PlanError
from csql_sim.core.files.pddl_import import TABLE_NAME, BlocksProblem
from csql_sim.core.state.state import default_name
from csql_sim.core.state.world import TABLE, Action, ActionKind

_PICKS = (ActionKind.PICKUP, ActionKind.UNSTACK)


@dataclass(frozen=True)
class Spelling:
    """How a problem's plan is written.

    Attributes:
        style: ``"4op"``, ``"move"`` or ``"csql"`` (:attr:`BlocksProblem.style`).
        words: operator -> the name written (``pickup``, ``putdown``, ``stack``, ``unstack``;
            for ``move``: ``b-b``, ``b-t``, ``t-b``).
        names: the blocks' names.
        table: the table object's name (the one-operator ``move`` names it), or None.
    """

    style: str
    words: dict[str, str]
    names: tuple[str, ...]
    table: str | None = None


def _pick(actions: frozenset[str] | None, *choices: str) -> str:
    """The first of ``choices`` the domain has (the first without a domain)."""
    return next((c for c in choices if actions is None or c in actions), choices[0])


def spelling_of(problem: BlocksProblem) -> Spelling:
    """The vocabulary of ``problem``'s plans (see the module docstring)."""
    acts = problem.actions
    if problem.style == "csql":
        return Spelling("csql", {}, problem.names)
    if problem.style == "4op":
        words = {"pickup": _pick(acts, "pick-up", "pickup"), "putdown": _pick(acts, "put-down", "putdown"),
                 "stack": "stack", "unstack": "unstack"}
        return Spelling("4op", words, problem.names)
    one = "move" in acts if acts is not None else problem.table is not None
    table = problem.table or TABLE_NAME
    if one:
        to_table = next((a for a in ("move-to-table", "move_to_table") if acts is not None and a in acts), None)
        return Spelling("move", {"b-b": "move", "t-b": "move", "b-t": to_table or "move"}, problem.names, table)
    words = {"b-b": "move-b-to-b", "t-b": "move-t-to-b", "b-t": _pick(acts, "move-b-to-t", "move-to-t")}
    return Spelling("move", words, problem.names, table)


def spelled_plan_lines(actions: Sequence[Action], spelling: Spelling) -> list[str]:
    """The plan's lines in ``spelling``; raises PlanError where a move domain cannot say it."""
    names = spelling.names
    if spelling.style == "csql":
        return [f"({a.kind.value}_{default_name(a.block).lower()}"
                f"{'' if a.target is None else '_' + default_name(a.target).lower()})" for a in actions]
    if spelling.style == "4op":
        return ["(" + " ".join([spelling.words[a.kind.value], names[a.block],
                                *(() if a.target is None else (names[a.target],))]) + ")" for a in actions]
    if len(actions) % 2 or any(a.kind not in _PICKS for a in actions[::2]) or \
            any(a.kind in _PICKS for a in actions[1::2]):
        raise PlanError("a move domain takes plans of picks each followed by a put; this plan is not")
    return [_move(pick, put, spelling) for pick, put in zip(actions[::2], actions[1::2], strict=True)]


def _move(pick: Action, put: Action, spelling: Spelling) -> str:
    """One pick and the put after it as one move of the domain."""
    names, words = spelling.names, spelling.words
    if pick.block != put.block:
        raise PlanError(f"a move domain cannot write a pick of {names[pick.block]} then a put of {names[put.block]}")
    source = TABLE if pick.target is None else pick.target
    dest = TABLE if put.target is None else put.target
    if source == dest == TABLE:
        raise PlanError(f"a move domain has no move of {names[pick.block]} from the table to the table")
    key = ("t" if source == TABLE else "b") + "-" + ("t" if dest == TABLE else "b")
    word = words[key]

    def name(i: int) -> str:
        return spelling.table if i == TABLE else names[i]

    if word == "move":
        args = [pick.block, source, dest]
    else:
        args = [pick.block] + ([] if source == TABLE else [source]) + ([] if dest == TABLE else [dest])
    return "(" + " ".join([word, *(name(i) for i in args)]) + ")"
