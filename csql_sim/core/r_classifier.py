"""R-classifiers: the paper's domain knowledge (Figure 5), loaded for n=3, generated for any n.

An R-classifier is one of two typed records (section 5):

* :class:`PreconditionRule` (Figure 5a): ``if condition then action message``;
* :class:`AddDeleteRule` (Figure 5b): ``if condition then output``, where the output
  rewrites the matched state message (``#`` copies its character).

In a rule file both are written ``kind: R`` with a condition and the posted message; the
posted message's tag (``A`` for an action message, ``S`` for a state message) tells which
record it is, and :func:`parse_r_classifier` is the one place that reads it.

Two rules per action, in the stable action order:

* a **precondition** rule (Figure 5a): its condition accepts exactly the state messages in
  which the action is legal, and its action is the action message;
* an **add-delete** rule (Figure 5b): its condition is ``S`` plus the action code in the
  action slot, and its output rewrites the fields the action changes (``#`` copies).

For n=3 the 36 rules are data, ``assets/rules/blocks3.yaml`` (installed as
``csql_sim.assets``), string for string the paper's table as restored in
docs/encoding.md; for other n they are generated from the four STRIPS operators by
:func:`generate_rules` (which also reproduces the n=3 table).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import ClassVar

import yaml

from csql_sim.core.message import BLOCK_FIELD, action_code, format_action_message, layout
from csql_sim.core.world import BLOCK_NAMES, TABLE, Action, ActionKind, all_actions, check_n, preconditions
from csql_sim.infra.errors import CsqlError

ASSET = "blocks3.yaml"
WILDCARD = "#"
ACTION_TAG = "A"
STATE_TAG = "S"


@dataclass(frozen=True, slots=True)
class PreconditionRule:
    """Figure 5(a): the action message is a candidate when the condition matches.

    Attributes:
        condition: a pattern over state messages; ``#`` matches any character.
        action: the action message posted when the condition matches.

    """

    condition: str
    action: str
    kind: ClassVar[str] = "R"


@dataclass(frozen=True, slots=True)
class AddDeleteRule:
    """Figure 5(b): the state message after an action, from the message before it.

    Attributes:
        condition: matches a state message whose action slot holds the action's code.
        output: the next state message; ``#`` copies the matched message's character.

    """

    condition: str
    output: str
    kind: ClassVar[str] = "R"

    @property
    def action(self) -> str:
        """The posted message (the rule file's ``action`` column)."""
        return self.output

    def apply(self, message: str) -> str:
        """The output with every ``#`` replaced by the message's character."""
        return "".join(m if o == WILDCARD else o for o, m in zip(self.output, message, strict=True))


RClassifier = PreconditionRule | AddDeleteRule


def matches(condition: str, message: str) -> bool:
    """Holland matching: equal length, and every non-``#`` character equal.

    The reference semantics; :class:`csql_sim.core.classifier_list.PatternIndex` gives the same
    answers without scanning.
    """
    if len(condition) != len(message):
        return False
    return all(c == WILDCARD or c == m for c, m in zip(condition, message, strict=True))


def parse_r_classifier(condition: str, posted: str) -> RClassifier:
    """The typed R-classifier of a (condition, posted message) pair from a rule file.

    Raises:
        CsqlError: when the posted message is neither an action nor a state message.
    """
    if posted.startswith(ACTION_TAG):
        return PreconditionRule(condition, posted)
    if posted.startswith(STATE_TAG):
        return AddDeleteRule(condition, posted)
    raise CsqlError(f"R-classifier output {posted!r} is neither an action message (A...) nor a state message (S...)")


def _blank(n: int) -> list[str]:
    return [WILDCARD] * layout(n).length


def precondition_condition(action: Action, n: int) -> str:
    """The Figure 5(a) condition of ``action``: its STRIPS preconditions as a pattern."""
    lay = layout(n)
    pat = _blank(n)
    pat[0] = "S"
    for p in preconditions(action):
        if p.what == "held":
            pat[lay.held_pos] = "0" if p.value is None else BLOCK_NAMES[p.value].lower()
        elif p.what == "clear":
            pat[lay.clear_start + p.block] = "1"
        else:
            pat[lay.on_start + p.block] = "t" if p.value == TABLE else BLOCK_NAMES[p.value].lower()
    return "".join(pat)


def add_delete_rule(action: Action, n: int) -> tuple[str, str]:
    """The Figure 5(b) (condition, output) of ``action``."""
    lay = layout(n)
    cond = _blank(n)
    cond[0] = "S"
    code = action_code(action, n)
    cond[1 : 1 + lay.action_width] = list(code)
    out = _blank(n)
    out[0] = "S"
    out[1 : 1 + lay.action_width] = ["0"] * lay.action_width
    x = action.block
    name = BLOCK_NAMES[x].lower()
    if action.kind in (ActionKind.PICKUP, ActionKind.UNSTACK):
        out[lay.clear_start + x] = "0"
        if action.kind is ActionKind.UNSTACK:
            out[lay.clear_start + action.target] = "1"
        out[lay.on_start + x] = "0"
        out[lay.held_pos] = name
    elif action.kind is ActionKind.PUTDOWN:
        out[lay.clear_start + x] = "1"
        out[lay.on_start + x] = "t"
        out[lay.held_pos] = "0"
    else:
        out[lay.clear_start + x] = "1"
        out[lay.clear_start + action.target] = "0"
        out[lay.on_start + x] = BLOCK_NAMES[action.target].lower()
        out[lay.held_pos] = "0"
    return "".join(cond), "".join(out)


def generate_rules(n: int) -> list[RClassifier]:
    """All R-classifiers for n blocks: the preconditions, then the add-delete rules."""
    check_n(n)
    assert BLOCK_FIELD >= n
    actions = all_actions(n)
    pre: list[RClassifier] = [PreconditionRule(precondition_condition(a, n), format_action_message(a, n))
                              for a in actions]
    post = [AddDeleteRule(*add_delete_rule(a, n)) for a in actions]
    return pre + post


def load_paper_rules() -> list[RClassifier]:
    """The 36 R-classifiers of the paper (n=3), read from the packaged asset.

    The asset is a rule file like any other (``csql_sim.core.rulebase`` reads it too); its
    rows are parsed here directly, so the R-classifier does not depend on the rule-file
    reader that is built on top of it.
    """
    doc = yaml.safe_load(_asset_text(ASSET))
    rows = doc["classifiers"]
    if doc.get("count") != len(rows) or any(row.get("kind") != "R" for row in rows):
        raise CsqlError(f"the packaged {ASSET} is damaged (reinstall csql-sim)")
    return [parse_r_classifier(row["condition"], row["action"]) for row in rows]


def _asset_text(name: str) -> str:
    """A rule asset's text: the installed ``csql_sim.assets``, else the checkout's ``assets/``.

    The second case is a source checkout that shadows the installed package (``python -m``
    run inside it puts the checkout first on ``sys.path``), where ``csql_sim.assets`` exists
    only as the top-level folder.
    """
    try:
        return resources.files("csql_sim.assets").joinpath("rules", name).read_text(encoding="utf-8")
    except ModuleNotFoundError:
        return (Path(__file__).resolve().parents[2] / "assets" / "rules" / name).read_text(encoding="utf-8")


@functools.cache
def r_classifiers(n: int) -> tuple[RClassifier, ...]:
    """The R-classifiers for n blocks: the paper's asset for n=3, generated otherwise.

    The records are immutable, so one tuple per n is shared.
    """
    return tuple(load_paper_rules() if n == 3 else generate_rules(n))
