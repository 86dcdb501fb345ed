"""Lifting: the schemas behind discovered ground R-classifiers, with variables for blocks.

Every ground rule names its action (a precondition rule posts its action message, an
add-delete rule's condition holds its action code), so its blocks have roles: the block
moved becomes ``?x`` and the block it comes from or goes onto ``?y``. :func:`lift_rule`
replaces them in every fixed field of the rule's pattern (the condition of a precondition
rule, the output of an add-delete rule) and returns the
:class:`~csql_sim.core.classifiers.lifted_rule.LiftedRule`, or a reason why the rule has no lifted form
(a fixed field about a third block, a fixed goal code).

:func:`lift_rules` induces the lifted rule set: per schema (operator and rule kind), the
ground rules of all its instances must lift to one and the same lifted rule, and every
instance must have been discovered; a schema that fails either test is reported, not
lifted. The lifted rules are then grounded again and compared string for string with the
ground rules they came from, so what is written out always reproduces what was found.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from csql_sim.core.classifiers.lifted_rule import (
    OPERATORS,
    POST,
    PRE,
    Field,
    LiftedRule,
    X,
    Y,
    bindings,
    ground_rules,
)
from csql_sim.core.classifiers.r_classifier import WILDCARD, PreconditionRule, RClassifier
from csql_sim.core.state.message import BLOCK_FIELD, decode_code, layout, parse_action_message
from csql_sim.core.state.world import BLOCK_NAMES, Action, all_actions


@dataclass(frozen=True)
class Lifted:
    """One ground rule's lifted form, or why it has none.

    Attributes:
        rule: the lifted rule (None when it cannot be lifted).
        action: the ground rule's action.
        reason: why not ("" when lifted).
    """

    rule: LiftedRule | None
    action: Action
    reason: str = ""


def _roles(action: Action) -> dict[int, str]:
    roles = {action.block: X}
    if action.target is not None:
        roles[action.target] = Y
    return roles


def _value(ch: str, roles: dict[int, str]) -> str | None:
    if ch in "t01":
        return ch
    block = BLOCK_NAMES.lower().find(ch)
    return roles.get(block)


def _fields(pattern: str, n: int, roles: dict[int, str]) -> tuple[tuple[Field, ...], str]:
    """The fixed fields of a state pattern with blocks replaced by their roles, and a problem ("" if none)."""
    lay = layout(n)
    out = []
    for what, start in (("clear", lay.clear_start), ("on", lay.on_start)):
        for i in range(BLOCK_FIELD):
            ch = pattern[start + i]
            if ch == WILDCARD:
                continue
            var, value = roles.get(i), _value(ch, roles)
            if var is None or value is None:
                return (), (f"position {start + i} ({what} of {BLOCK_NAMES[i]}) is about a block "
                            f"the action does not name")
            out.append(Field(what, var, value))
    held = pattern[lay.held_pos]
    if held != WILDCARD:
        value = _value(held, roles)
        if value is None:
            return (), f"position {lay.held_pos} (held) names a block the action does not name"
        out.append(Field("held", None, value))
    if set(pattern[lay.goal_start:]) != {WILDCARD}:
        return (), "the goal code is fixed"
    return tuple(sorted(out, key=Field.sort_key)), ""


def lift_rule(rule: RClassifier, n: int) -> Lifted:
    """The lifted form of one ground R-classifier of n blocks (see the module docstring)."""
    lay = layout(n)
    if isinstance(rule, PreconditionRule):
        action = parse_action_message(rule.action, n)
        fields, problem = _fields(rule.condition, n, _roles(action))
        kind = PRE
    else:
        action = all_actions(n)[decode_code(lay.action_slot(rule.condition)) - 1]
        fields, problem = _fields(rule.output, n, _roles(action))
        if set(rule.condition[1 + lay.action_width:]) != {WILDCARD}:
            problem = problem or "the condition fixes more than the action slot"
        if lay.action_slot(rule.output) != "0" * lay.action_width:
            problem = problem or "the output does not reset the action slot"
        kind = POST
    if problem:
        return Lifted(None, action, problem)
    return Lifted(LiftedRule(kind, action.kind, fields), action)


@dataclass
class Lifting:
    """The lifted rules induced from ground rules, and the schemas that could not be lifted.

    Attributes:
        n: number of blocks of the ground rules.
        rules: the lifted rules, preconditions first, in the stable operator order.
        problems: per schema not lifted (e.g. ``"precondition unstack"``), why.
    """

    n: int
    rules: list[LiftedRule] = field(default_factory=list)
    problems: dict[str, str] = field(default_factory=dict)

    def lines(self) -> list[str]:
        """The lifted rules in the documented syntax, then one line per schema not lifted."""
        return [r.text() for r in self.rules] + [f"not lifted: {k}: {v}" for k, v in self.problems.items()]


def lift_rules(rules: list[RClassifier], n: int) -> Lifting:
    """Induce the lifted rules from ground R-classifiers of n blocks (see the module docstring)."""
    lifted = [lift_rule(r, n) for r in rules]
    out = Lifting(n)
    for kind in (PRE, POST):
        for op in OPERATORS:
            name = f"{kind} {op.value}"
            mine = [(g, x) for g, x in zip(rules, lifted, strict=True)
                    if x.action.kind is op and (x.rule is None or x.rule.kind == kind)
                    and isinstance(g, PreconditionRule) == (kind == PRE)]
            problem = _schema_problem(mine, op, n)
            if problem:
                out.problems[name] = problem
            else:
                out.rules.append(mine[0][1].rule)
    return out


def _schema_problem(mine: list[tuple[RClassifier, Lifted]], op, n: int) -> str:
    """Why the instances of one schema do not lift to one rule that grounds back to them ("" if they do)."""
    if not mine:
        return "no ground rule was discovered"
    failed = [x for _, x in mine if x.rule is None]
    if failed:
        return failed[0].reason
    forms = {x.rule for _, x in mine}
    if len(forms) > 1:
        return f"its {len(mine)} ground rules lift to {len(forms)} different rules"
    expected = sum(1 for _ in bindings(op, n))
    if len(mine) != expected:
        return f"{len(mine)} of its {expected} ground rules were discovered"
    rule = next(iter(forms))
    grounded = [(r.condition, r.action) for r in ground_rules([rule], n)]
    found = sorted((g.condition, g.action) for g, _ in mine)
    return "" if sorted(grounded) == found else "its lifted rule does not ground back to the discovered ones"
