"""Lifted R-classifiers: the paper's Figure 5 rules with variables in place of block letters.

The 36 R-classifiers of the paper are four schemas (pick a block from a block, pick one
from the table, put one on the table, stack one on another), each written out as a
precondition rule and an add-delete rule for every pair of letters. A lifted rule writes
the schema once, with the variables ``?x`` (the block moved) and ``?y`` (the block it comes
from or goes onto); the table is ``t`` and the gripper ``0`` exactly as in the messages.

Syntax, one rule per line (``R`` as in the paper's table, then the condition, then what
the rule posts)::

    R S[held=0 clear(?x)=1 on(?x)=?y] A[unstack(?x,?y)]
    R S[act=unstack(?x,?y)] S[clear(?x)=0 clear(?y)=1 on(?x)=0 held=?x]

* ``S[...]`` is a state-message pattern: the fields it names are fixed, every other
  position is ``#``. Fields: ``clear(V)=1|0``; ``on(V)=t`` (the table), ``on(V)=0`` (held)
  or ``on(V)=W`` (on the block bound to W); ``held=0`` (hand empty) or ``held=V``;
  ``act=OP`` (the action slot holds OP's action code; add-delete conditions only).
* ``A[OP]`` is the action message of OP; ``OP`` is ``unstack(?x,?y)``, ``pickup(?x)``,
  ``putdown(?x)`` or ``stack(?x,?y)`` (the tool's action names).
* A precondition rule is ``S[...] A[OP]``; an add-delete rule is ``S[act=OP] S[...]``,
  whose output also resets the action slot to ``0`` (as every Figure 5b output does).
* Fields are written in message order: ``act``, the clear fields, the on fields, ``held``;
  ``?x`` before ``?y`` within a field kind. Distinct variables name distinct blocks.

:func:`ground_rules` writes the lifted rules out for n blocks: every binding of the
variables to distinct blocks, in the stable action order, as the R-classifier strings of
:mod:`csql_sim.core.classifiers.r_classifier`. Grounding :data:`BLOCKS_WORLD` gives exactly the
tool's R-classifiers (the paper's asset at n = 3, the generator's otherwise).
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from csql_sim.core.classifiers.r_classifier import WILDCARD, AddDeleteRule, PreconditionRule, RClassifier
from csql_sim.core.state.message import action_code, format_action_message, layout
from csql_sim.core.state.world import BLOCK_NAMES, HAND, TABLE, Action, ActionKind, check_n
from csql_sim.infra import formats
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import InputFileError, load_json, read_text_file

X, Y = "?x", "?y"
"""The variables: the block moved, and the block it comes from or goes onto."""
PRE, POST = "precondition", "add-delete"
OPERATORS = (ActionKind.UNSTACK, ActionKind.PICKUP, ActionKind.PUTDOWN, ActionKind.STACK)
"""The four schemas in the stable action order of :func:`csql_sim.core.state.world.all_actions`."""
FIELD_ORDER = {"act": 0, "clear": 1, "on": 2, "held": 3}


class LiftedRuleError(CsqlError):
    """A lifted rule that does not follow the documented syntax."""


def operator_variables(kind: ActionKind) -> tuple[str, ...]:
    """The variables an operator binds: ``(?x, ?y)`` for unstack and stack, ``(?x,)`` otherwise."""
    return (X, Y) if kind in (ActionKind.UNSTACK, ActionKind.STACK) else (X,)


def operator_term(kind: ActionKind) -> str:
    """``unstack(?x,?y)``, ``pickup(?x)``, ..."""
    return f"{kind.value}({','.join(operator_variables(kind))})"


@dataclass(frozen=True)
class Field:
    """One fixed field of a lifted state pattern.

    Attributes:
        what: ``"clear"``, ``"on"`` or ``"held"`` (the ``act`` field is the rule's operator).
        var: the variable whose slot it is (None for ``held``).
        value: ``"1"``/``"0"`` for clear; ``"t"``, ``"0"`` or a variable for on; ``"0"`` or
            a variable for held.
    """

    what: str
    var: str | None
    value: str

    def text(self) -> str:
        """``clear(?x)=1``, ``on(?x)=t``, ``held=?x``."""
        return f"{self.what}={self.value}" if self.var is None else f"{self.what}({self.var})={self.value}"

    def sort_key(self) -> tuple[int, str]:
        return FIELD_ORDER[self.what], self.var or ""


@dataclass(frozen=True)
class LiftedRule:
    """One lifted R-classifier (see the module docstring).

    Attributes:
        kind: :data:`PRE` (Figure 5a) or :data:`POST` (Figure 5b).
        operator: the schema's operator.
        fields: the precondition's condition, or the add-delete rule's output, in message order.
    """

    kind: str
    operator: ActionKind
    fields: tuple[Field, ...]

    def text(self) -> str:
        """The rule in the documented one-line syntax."""
        state = "S[" + " ".join(f.text() for f in self.fields) + "]"
        term = operator_term(self.operator)
        if self.kind == PRE:
            return f"R {state} A[{term}]"
        return f"R S[act={term}] {state}"

    def __str__(self) -> str:
        return self.text()

    def sort_key(self) -> tuple[int, int]:
        """Preconditions before add-delete rules, each in the stable operator order."""
        return (0 if self.kind == PRE else 1), OPERATORS.index(self.operator)


_RULE = re.compile(r"^R\s+S\[([^\]]*)\]\s+([AS])\[([^\]]*)\]$")
_FIELD = re.compile(r"^(clear|on)\((\?[a-z])\)=(\S+)$|^(held)=(\S+)$")
_TERM = re.compile(r"^(unstack|pickup|putdown|stack)\(([^)]*)\)$")


def _operator(term: str, line: str) -> ActionKind:
    found = _TERM.match(term.replace(" ", ""))
    if not found:
        raise LiftedRuleError(f"lifted rule {line!r}: {term!r} is not an operator such as unstack(?x,?y)")
    kind = ActionKind(found.group(1))
    if tuple(found.group(2).split(",")) != operator_variables(kind):
        raise LiftedRuleError(f"lifted rule {line!r}: write the operator as {operator_term(kind)}")
    return kind


def _field(token: str, variables: tuple[str, ...], line: str) -> Field:
    found = _FIELD.match(token)
    if not found:
        raise LiftedRuleError(f"lifted rule {line!r}: {token!r} is not a field such as clear(?x)=1")
    what, var, value = (found.group(1), found.group(2), found.group(3)) if found.group(1) else \
        (found.group(4), None, found.group(5))
    allowed = {"clear": ("0", "1"), "on": ("t", "0", *variables), "held": ("0", *variables)}[what]
    if var is not None and var not in variables:
        raise LiftedRuleError(f"lifted rule {line!r}: variable {var} is not bound by the operator")
    if value not in allowed or value == var:
        raise LiftedRuleError(f"lifted rule {line!r}: {token!r} must have one of {', '.join(allowed)}"
                              + (f" other than {var}" if value == var else ""))
    return Field(what, var, value)


def _fields(body: str, variables: tuple[str, ...], line: str) -> tuple[Field, ...]:
    fields = tuple(_field(t, variables, line) for t in body.split())
    keys = [(f.what, f.var) for f in fields]
    if len(set(keys)) != len(keys):
        raise LiftedRuleError(f"lifted rule {line!r} fixes one field twice")
    return tuple(sorted(fields, key=Field.sort_key))


def parse_lifted_rule(line: str) -> LiftedRule:
    """Read one lifted rule in the documented syntax.

    Raises:
        LiftedRuleError: one line naming the rule and what is wrong with it.
    """
    text = " ".join(line.split())
    found = _RULE.match(text)
    if not found:
        raise LiftedRuleError(f"lifted rule {line!r} is not 'R S[fields] A[operator]' or "
                              f"'R S[act=operator] S[fields]'")
    condition, tag, posted = found.groups()
    if tag == "A":
        kind = _operator(posted, line)
        return LiftedRule(PRE, kind, _fields(condition, operator_variables(kind), line))
    head = condition.strip()
    if not head.startswith("act="):
        raise LiftedRuleError(f"lifted rule {line!r}: an add-delete condition is S[act=operator] alone")
    kind = _operator(head[4:], line)
    return LiftedRule(POST, kind, _fields(posted, operator_variables(kind), line))


def parse_lifted_rules(lines: Iterable[str]) -> tuple[LiftedRule, ...]:
    """Read lifted rules, one per non-blank line (``#`` starts a comment line)."""
    return tuple(parse_lifted_rule(s) for s in lines if s.strip() and not s.lstrip().startswith("#"))


BLOCKS_WORLD_TEXT = (
    "R S[clear(?x)=1 on(?x)=?y held=0] A[unstack(?x,?y)]",
    "R S[clear(?x)=1 on(?x)=t held=0] A[pickup(?x)]",
    "R S[held=?x] A[putdown(?x)]",
    "R S[clear(?y)=1 held=?x] A[stack(?x,?y)]",
    "R S[act=unstack(?x,?y)] S[clear(?x)=0 clear(?y)=1 on(?x)=0 held=?x]",
    "R S[act=pickup(?x)] S[clear(?x)=0 on(?x)=0 held=?x]",
    "R S[act=putdown(?x)] S[clear(?x)=1 on(?x)=t held=0]",
    "R S[act=stack(?x,?y)] S[clear(?x)=1 clear(?y)=0 on(?x)=?y held=0]",
)
"""The four schemas as the paper's Figure 5 has them, lifted (the reference for discovery)."""
BLOCKS_WORLD = parse_lifted_rules(BLOCKS_WORLD_TEXT)


# ---------------------------------------------------------------- grounding


def bindings(kind: ActionKind, n: int) -> Iterator[dict[str, int]]:
    """Every binding of the operator's variables to distinct blocks, in the stable action order."""
    if len(operator_variables(kind)) == 1:
        for x in range(n):
            yield {X: x}
        return
    for x in range(n):
        for y in range(n):
            if x != y:
                yield {X: x, Y: y}


def bound_action(kind: ActionKind, binding: dict[str, int]) -> Action:
    """The action the operator names under ``binding``."""
    return Action(kind, binding[X], binding.get(Y))


def _value_char(value: str, binding: dict[str, int]) -> str:
    return value if value in ("t", "0", "1") else BLOCK_NAMES[binding[value]].lower()


def _write(pattern: list[str], fields: tuple[Field, ...], binding: dict[str, int], n: int) -> None:
    lay = layout(n)
    for f in fields:
        if f.what == "held":
            pos = lay.held_pos
        else:
            pos = (lay.clear_start if f.what == "clear" else lay.on_start) + binding[f.var]
        pattern[pos] = _value_char(f.value, binding)


def ground_rule(rule: LiftedRule, binding: dict[str, int], n: int) -> RClassifier:
    """The ground R-classifier of ``rule`` with its variables bound (n-block message strings)."""
    lay = layout(n)
    action = bound_action(rule.operator, binding)
    pattern = ["S"] + [WILDCARD] * (lay.length - 1)
    if rule.kind == PRE:
        _write(pattern, rule.fields, binding, n)
        return PreconditionRule("".join(pattern), format_action_message(action, n))
    condition = "S" + action_code(action, n) + WILDCARD * (lay.length - 1 - lay.action_width)
    pattern[1 : 1 + lay.action_width] = ["0"] * lay.action_width
    _write(pattern, rule.fields, binding, n)
    return AddDeleteRule(condition, "".join(pattern))


def ground_rules(rules: Iterable[LiftedRule], n: int) -> list[RClassifier]:
    """Every rule under every binding at n blocks, rule by rule in the given order.

    With the rules in :meth:`LiftedRule.sort_key` order (as :data:`BLOCKS_WORLD` is) this is
    the order of :func:`csql_sim.core.classifiers.r_classifier.generate_rules`.
    """
    check_n(n)
    return [ground_rule(r, b, n) for r in rules for b in bindings(r.operator, n)]


# ---------------------------------------------------------------- on relational states


def field_holds(f: Field, support: tuple[int, ...], clear: tuple[bool, ...], held: int | None,
                binding: dict[str, int]) -> bool:
    """Whether one field is true of a state given as support, clear and held (any n)."""
    if f.what == "clear":
        return clear[binding[f.var]] == (f.value == "1")
    if f.what == "held":
        return held == (None if f.value == "0" else binding[f.value])
    want = TABLE if f.value == "t" else HAND if f.value == "0" else binding[f.value]
    return support[binding[f.var]] == want


def apply_output(rule: LiftedRule, support: tuple[int, ...], binding: dict[str, int]) -> tuple[int, ...]:
    """The support vector after an add-delete rule's output (clear and held follow from it)."""
    out = list(support)
    for f in rule.fields:
        if f.what == "on":
            out[binding[f.var]] = TABLE if f.value == "t" else HAND if f.value == "0" else binding[f.value]
    return tuple(out)


# ---------------------------------------------------------------- the lifted rule file

LIFTED_FORMAT = formats.LIFTED_RULES
LIFTED_VERSION = 1
MAX_LIFTED_BYTES = 1 << 20


def dumps_lifted(rules: Iterable[LiftedRule], meta: dict) -> str:
    """A lifted rule file: JSON with the format, its version, ``meta`` and the rules as lines."""
    doc = {"format": LIFTED_FORMAT, "version": LIFTED_VERSION, "meta": meta, "rules": [r.text() for r in rules]}
    return json.dumps(doc, indent=2) + "\n"


def read_versioned_json(text: str, source: str, fmt: str, version: int | tuple[int, ...],
                        error: type[CsqlError]) -> dict:
    """A JSON object that names its format ``fmt`` and ``version`` (or one of them); else ``error`` in one line."""
    try:
        doc = load_json(text, source)  # bounded nesting and digits: one line, never a RecursionError
    except InputFileError as exc:
        raise error(str(exc)) from None
    if not isinstance(doc, dict) or doc.get("format") != fmt:
        raise error(f"{source} is not a {fmt} file")
    versions = version if isinstance(version, tuple) else (version,)
    if type(doc.get("version")) is not int or doc["version"] not in versions:
        raise error(f"{source} has version {doc.get('version')!r}; this csql-sim reads "
                    f"{' or '.join(map(str, versions))}")
    return doc


def loads_lifted(text: str, source: str = "lifted rule file") -> tuple[LiftedRule, ...]:
    """The rules of a lifted rule file's text.

    Raises:
        LiftedRuleError: one line naming the source and what is wrong.
    """
    doc = read_versioned_json(text, source, LIFTED_FORMAT, LIFTED_VERSION, LiftedRuleError)
    rules = doc.get("rules")
    if not isinstance(rules, list) or not all(isinstance(r, str) for r in rules):
        raise LiftedRuleError(f"{source}: 'rules' must be a list of lifted rules, one string each")
    return parse_lifted_rules(rules)


def load_lifted(path: str | os.PathLike) -> tuple[LiftedRule, ...]:
    """Read a lifted rule file (regular file, size-capped)."""
    text = read_text_file(path, MAX_LIFTED_BYTES, "lifted rule file")
    return loads_lifted(text, f"lifted rule file {os.fspath(path)!r}")
