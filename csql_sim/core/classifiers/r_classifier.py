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

:func:`validate_r_classifier` is the one check of a rule against the n-block message
grammar; both rule-file codecs, :class:`~csql_sim.core.model.world_model.WorldModel` and the
PDDL export make it, so every reader refuses the same rules.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import ClassVar

import yaml

from csql_sim.core.state.message import (
    BLOCK_FIELD,
    DIGITS,
    MessageError,
    action_code,
    decode_code,
    format_action_message,
    layout,
    parse_action_message,
)
from csql_sim.core.state.world import (
    BLOCK_NAMES,
    TABLE,
    Action,
    ActionKind,
    all_actions,
    all_states,
    check_n,
    preconditions,
)
from csql_sim.infra.assets import asset_text
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

    The reference semantics; :class:`csql_sim.core.classifiers.classifier_list.PatternIndex` gives the same
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


class RuleError(CsqlError):
    """An R-classifier that does not fit the message grammar of its number of blocks."""


def validate_r_classifier(rule: RClassifier, n: int, owner: str = "rules") -> None:
    """Refuse an R-classifier that no n-block world can hold: the one check every reader makes.

    Both rule-file codecs (through :func:`r_classifier_problem`), :class:`WorldModel
    <csql_sim.core.model.world_model.WorldModel>` and the PDDL export call it. See
    :func:`r_classifier_problem` for what is checked.

    Raises:
        RuleError: one line naming the string, the position and what is wrong.
    """
    problem = r_classifier_problem(rule.condition, rule.action, n, owner)
    if problem:
        raise RuleError(problem)


def r_classifier_problem(condition: object, posted: object, n: int, owner: str = "rules") -> str | None:
    """Why ``(condition, posted)`` is no R-classifier of n blocks; None if it is one.

    * Both strings have the n-block message length and only characters of the message
      grammar at each position (no other letter, no block beyond n, no block on itself;
      ``#`` wherever a state-message pattern has a field).
    * A precondition rule posts a complete action message (no ``#``).
    * An add-delete rule's condition names one action code in its action slot; its output
      resets the slot to ``0`` and fixes the moved block's on field and the hand only as
      that action does.
    * A condition or output describes a possible state: no two blocks held, the hand and
      the on fields agree, a held or covered block is not clear, one block on each block,
      no cycle. Codes in the action slot and the goal field are within the n-block world.

    ``owner`` names what states n in the messages ("file": "but the file is for 2 blocks").
    """
    width = layout(n).length
    for name, text in (("condition", condition), ("action", posted)):
        if not isinstance(text, str) or len(text) != width:
            return f"{name} must be a {width}-character string, got {text!r}"
    return _problem(condition, posted, n, owner)


@functools.lru_cache(maxsize=8192)
def _problem(condition: str, posted: str, n: int, owner: str) -> str | None:
    """:func:`r_classifier_problem` for strings of the right length (memoized: rules repeat)."""
    problem = _pattern_problem(condition, n, owner)
    if problem:
        return f"condition {condition!r}: {problem}"
    if posted.startswith(ACTION_TAG):
        problem = _foreign_block(posted, n, owner)
        if problem is None:
            try:
                parse_action_message(posted, n)
            except MessageError as exc:
                problem = f"not a {n}-block action message ({exc})"
        return f"action {posted!r}: {problem}" if problem else None
    if not posted.startswith(STATE_TAG):
        return f"R-classifier output {posted!r} is neither an action message (A...) nor a state message (S...)"
    problem = _pattern_problem(posted, n, owner)
    if problem:
        return f"output {posted!r}: {problem}"
    return _add_delete_problem(condition, posted, n)


@functools.cache
def _pattern_chars(n: int) -> tuple[str, ...]:
    """The characters a state-message pattern of n blocks may hold, position by position (``#`` included)."""
    lay = layout(n)
    names = BLOCK_NAMES[:n].lower()
    chars = ["S"] + [DIGITS + WILDCARD] * lay.action_width
    chars += ["01#" if i < n else "0#" for i in range(BLOCK_FIELD)]
    chars += ["t0" + names.replace(names[i], "") + WILDCARD if i < n else "0#" for i in range(BLOCK_FIELD)]
    return tuple([*chars, "0" + names + WILDCARD] + [DIGITS + WILDCARD] * lay.goal_width)


def _foreign_block(text: str, n: int, owner: str) -> str | None:
    """The first lower-case block letter beyond the n blocks, as a problem (None if there is none)."""
    for pos, ch in enumerate(text):
        if ch in BLOCK_NAMES.lower()[n:]:
            return f"position {pos} names block {ch.upper()}, but the {owner} is for {n} blocks"
    return None


def _pattern_problem(text: str, n: int, owner: str) -> str | None:
    """Why ``text`` is no state-message pattern of n blocks (None if it is one)."""
    lay = layout(n)
    problem = _foreign_block(text, n, owner)
    if problem:
        return problem
    for pos, (ch, allowed) in enumerate(zip(text, _pattern_chars(n), strict=True)):
        if ch in allowed:
            continue
        if lay.on_start <= pos < lay.on_start + n and ch == BLOCK_NAMES[pos - lay.on_start].lower():
            return f"position {pos} puts block {ch.upper()} on itself"
        if not ch.isascii() or not ch.isprintable():
            return f"position {pos} is {ascii(ch)}, not a message character"
        shown = "a base-36 digit (0-9, A-Z) or #" if allowed.startswith(DIGITS) else "one of " + allowed
        return f"position {pos} is {ch!r}, expected {shown}"
    code = lay.action_slot(text)
    if WILDCARD not in code and decode_code(code) > len(all_actions(n)):
        return f"action code {code} is beyond the {len(all_actions(n))} actions of {n} blocks"
    goal, states = text[lay.goal_start:], len(all_states(n))
    if WILDCARD not in goal and decode_code(goal) >= states:
        return f"goal code {goal} is beyond the {states} states of {n} blocks"
    return _impossible(text, n)


def _impossible(text: str, n: int) -> str | None:
    """Why the fixed fields of a state pattern describe no state (None if some state fits them)."""
    lay = layout(n)
    names = BLOCK_NAMES[:n].lower()
    clear = {i: text[lay.clear_start + i] for i in range(n)}
    on = {i: text[lay.on_start + i] for i in range(n) if text[lay.on_start + i] != WILDCARD}
    hand = text[lay.held_pos]
    holders = [BLOCK_NAMES[i] for i, ch in on.items() if ch == "0"]
    if len(holders) > 1:
        return f"blocks {' and '.join(holders)} are both held (on field 0)"
    if holders and hand not in (WILDCARD, holders[0].lower()):
        return f"block {holders[0]} is held (on field 0), but the hand field is {hand!r}"
    held = {BLOCK_NAMES.index(b) for b in holders} | ({names.index(hand)} if hand in names else set())
    below: dict[int, int] = {}
    for i, ch in on.items():
        if i in held and ch != "0":
            return f"block {BLOCK_NAMES[i]} is held but stands on {ch!r}"
        if ch in names:
            j = names.index(ch)
            why = ("is held" if j in held else "is marked clear" if clear[j] == "1"
                   else f"already holds {BLOCK_NAMES[below[j]]}" if j in below else None)
            if why:
                return f"block {BLOCK_NAMES[i]} is on {BLOCK_NAMES[j]}, which {why}"
            below[j] = i
    if any(clear[i] == "1" for i in held):
        return "a held block is marked clear"
    for i in on:
        seen, j = {i}, on[i]
        while j in names and (k := names.index(j)) in on:
            if k in seen:
                return f"the blocks form a cycle through {BLOCK_NAMES[i]}"
            seen.add(k)
            j = on[k]
    return None


def _add_delete_problem(condition: str, output: str, n: int) -> str | None:
    """Why an add-delete rule's condition and output do not describe one action (None if they do)."""
    lay = layout(n)
    count = len(all_actions(n))
    code = lay.action_slot(condition)
    if WILDCARD in code or decode_code(code) == 0:
        return f"condition {condition!r}: its action slot must hold one action code 1..{count}, got {code!r}"
    if lay.action_slot(output) != "0" * lay.action_width:
        return f"output {output!r}: its action slot must be reset to {'0' * lay.action_width}"
    action = all_actions(n)[decode_code(code) - 1]
    name = BLOCK_NAMES[action.block].lower()
    if action.is_pick:
        hand, on = name, "0"
    else:
        hand, on = "0", "t" if action.target is None else BLOCK_NAMES[action.target].lower()
    for pos, want, what in ((lay.held_pos, hand, "hand"), (lay.on_start + action.block, on, "on field")):
        if output[pos] not in (WILDCARD, want):
            return (f"output {output!r}: after {action.name()} the {what} (position {pos}) must be {want!r} "
                    f"or #, not {output[pos]!r}")
    return None


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

    The asset is a rule file like any other (``csql_sim.core.files.rulebase`` reads it too); its
    rows are parsed here directly, so the R-classifier does not depend on the rule-file
    reader that is built on top of it.
    """
    doc = yaml.safe_load(_asset_text(ASSET))
    rows = doc["classifiers"]
    if doc.get("count") != len(rows) or any(row.get("kind") != "R" for row in rows):
        raise CsqlError(f"the packaged {ASSET} is damaged (reinstall csql-sim)")
    return [parse_r_classifier(row["condition"], row["action"]) for row in rows]


def _asset_text(name: str) -> str:
    """A rule asset's text (``assets/rules``)."""
    return asset_text("rules", name)


@functools.cache
def r_classifiers(n: int) -> tuple[RClassifier, ...]:
    """The R-classifiers for n blocks: the paper's asset for n=3, generated otherwise.

    The records are immutable, so one tuple per n is shared.
    """
    return tuple(load_paper_rules() if n == 3 else generate_rules(n))
