"""The world model of any set of R-classifiers as a STRIPS domain and problem in PDDL.

Every message field that describes the blocks (clear, on and held slots of the n blocks)
becomes a family of 0-ary facts, one per value: ``clear_a_1``, ``clear_a_0``, ``on_a_b``,
``on_a_t``, ``on_a_0`` (held), ``held_a``, ``held_0``. An action joins the precondition
rule that proposes its action message with the add-delete rule its code activates:

* precondition: the facts ``field_value`` of the condition's non-``#`` positions;
* effect: for each non-``#`` output position, add ``field_value`` and delete every other
  value of that field (deleting a false fact is harmless in STRIPS).

So the translation reads only the rules and the message layout, never the blocks-world
semantics: rules from ``csql-sim discover`` export the same way as Figure 5. The text is
produced by the ``pddl`` library's formatter, not by hand.

:func:`blocks_problem_text` writes a task of any n in the classic four-operator form
(``on``, ``ontable``, ``clear``, ``handempty``, ``holding``) with the blocks' own names,
which :mod:`csql_sim.core.files.pddl_import` reads back.
"""

from __future__ import annotations

from pddl.action import Action as PddlAction
from pddl.core import Domain, Problem
from pddl.formatter import domain_to_string, problem_to_string
from pddl.logic import Constant, Predicate
from pddl.logic.base import And, Not
from pddl.requirements import Requirements

from csql_sim.core.classifiers.r_classifier import (
    WILDCARD,
    AddDeleteRule,
    PreconditionRule,
    RClassifier,
    validate_r_classifier,
)
from csql_sim.core.state.message import format_state_message, layout, parse_action_message
from csql_sim.core.state.world import BLOCK_NAMES, TABLE, State
from csql_sim.infra.errors import CsqlError


class PddlError(CsqlError):
    """Rules that cannot be written as a PDDL domain."""


def _fields(n: int) -> dict[int, tuple[str, str]]:
    """Message position -> (field name, its possible values) for the blocks' fields."""
    lay = layout(n)
    names = BLOCK_NAMES[:n].lower()
    out = {}
    for i, b in enumerate(names):
        out[lay.clear_start + i] = (f"clear_{b}", "01")
        out[lay.on_start + i] = (f"on_{b}", "t0" + names.replace(b, ""))
    out[lay.held_pos] = ("held", "0" + names)
    return out


def _fact(name: str, value: str) -> Predicate:
    return Predicate(f"{name}_{value}")


def _facts_of(message: str, n: int) -> list[Predicate]:
    return [_fact(name, message[p]) for p, (name, _) in _fields(n).items()]


def _action(pre: PreconditionRule, post: AddDeleteRule, n: int) -> PddlAction:
    """One PDDL action; both rules are valid (:func:`build_domain` checked), so every character is a field value."""
    fields = _fields(n)
    need = [_fact(fields[p][0], ch) for p, ch in enumerate(pre.condition) if p in fields and ch != WILDCARD]
    effects = []
    for p, ch in enumerate(post.output):
        if p in fields and ch != WILDCARD:
            name, values = fields[p]
            effects.append(_fact(name, ch))
            effects += [Not(_fact(name, v)) for v in values if v != ch]
    act = parse_action_message(pre.action, n)
    label = act.name().lower().replace("(", "_").replace(",", "_").replace(")", "")
    return PddlAction(label, [], precondition=And(*need), effect=And(*effects))


def build_domain(rules: list[RClassifier], n: int) -> Domain:
    """The STRIPS domain of ``rules`` (R-classifiers for n blocks).

    Raises:
        RuleError: for a rule that does not fit the n-block messages (the check every reader makes).
        PddlError: when no action has both of its rules.
    """
    for rule in rules:
        validate_r_classifier(rule, n)
    w = layout(n).action_width
    pre = {r.action[1 : 1 + w]: r for r in rules if isinstance(r, PreconditionRule)}
    post = {r.condition[1 : 1 + w]: r for r in rules if isinstance(r, AddDeleteRule)}
    codes = [c for c in pre if c in post]
    if not codes:
        raise PddlError("no action has both a precondition and an add-delete rule")
    actions = [_action(pre[c], post[c], n) for c in codes]
    predicates = [_fact(name, v) for name, values in _fields(n).values() for v in values]
    return Domain(f"blocks{n}", requirements=[Requirements.STRIPS], predicates=predicates, actions=actions)


def build_problem(domain: Domain, start: State, goal: State) -> Problem:
    """The task from ``start`` to ``goal``: every field's fact in the start and in the goal."""
    n = start.n
    # domain_name, not domain: the problem then carries no :requirements of its own,
    # which some planners (pyperplan) reject in a problem file.
    return Problem(f"task{n}", domain_name=domain.name,
                   init=_facts_of(format_state_message(start, 0), n),
                   goal=And(*_facts_of(format_state_message(goal, 0), n)))


def domain_text(rules: list[RClassifier], n: int) -> str:
    """``domain.pddl``'s text."""
    return domain_to_string(build_domain(rules, n)) + "\n"


def problem_text(rules: list[RClassifier], start: State, goal: State) -> str:
    """``problem.pddl``'s text."""
    return problem_to_string(build_problem(build_domain(rules, start.n), start, goal)) + "\n"


def _state_atoms(state: State, objects: list[Constant]) -> list[Predicate]:
    """The four-operator atoms of ``state`` (``handempty`` or ``holding``, ``on``/``ontable``, ``clear``)."""
    held = state.held
    atoms = [Predicate("handempty") if held is None else Predicate("holding", objects[held])]
    for i, below in enumerate(state.support):
        if below == TABLE:
            atoms.append(Predicate("ontable", objects[i]))
        elif below >= 0:
            atoms.append(Predicate("on", objects[i], objects[below]))
        if state.is_clear(i):
            atoms.append(Predicate("clear", objects[i]))
    return atoms


def blocks_problem_text(start: State, goal: State, name: str = "task", domain: str = "blocksworld") -> str:
    """The task as a classic four-operator PDDL problem, objects named as ``start`` names its blocks.

    Default names are written in lower case (``a``, ``b``, ...), as plan files write them.
    """
    if start.n != goal.n:
        raise PddlError(f"start has {start.n} blocks but goal has {goal.n}")
    names = start.block_names if start.names is not None else tuple(x.lower() for x in start.block_names)
    objects = [Constant(x) for x in names]
    problem = Problem(name, domain_name=domain, objects=objects, init=_state_atoms(start, objects),
                      goal=And(*_state_atoms(goal, objects)))
    return problem_to_string(problem) + "\n"
