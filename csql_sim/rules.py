"""R-classifiers: the paper's domain knowledge (Figure 5), loaded for n=3, generated for any n.

Two rules per action, in the stable action order:

* a **precondition** rule (Figure 5a): its condition accepts exactly the state messages in
  which the action is legal, and its action is the action message;
* an **add-delete** rule (Figure 5b): its condition is ``S`` plus the action code in the
  action slot, and its output rewrites the fields the action changes (``#`` copies).

For n=3 the 36 rules are data, ``assets/rules/blocks3.yaml``, string for string equal to
encoding.md's table; for other n they are generated from the four STRIPS operators by
:func:`generate_rules` (which also reproduces the n=3 table).
"""

from __future__ import annotations

import functools
from importlib import resources

from csql_sim.classifiers import WILDCARD, Classifier, ClassifierList, R
from csql_sim.messages import BLOCK_FIELD, action_code, format_action_message, layout
from csql_sim.world import BLOCK_NAMES, ActionKind, all_actions, check_n

ASSET = "blocks3.yaml"


def _blank(n: int) -> list[str]:
    return [WILDCARD] * layout(n).length


def precondition_condition(action, n: int) -> str:
    """The Figure 5(a) condition of ``action``: the STRIPS preconditions as a pattern."""
    lay = layout(n)
    pat = _blank(n)
    pat[0] = "S"
    x = action.block
    if action.kind in (ActionKind.PICKUP, ActionKind.UNSTACK):
        pat[lay.clear_start + x] = "1"
        pat[lay.on_start + x] = "t" if action.kind is ActionKind.PICKUP else BLOCK_NAMES[action.target].lower()
        pat[lay.held_pos] = "0"
    elif action.kind is ActionKind.PUTDOWN:
        pat[lay.held_pos] = BLOCK_NAMES[x].lower()
    else:
        pat[lay.clear_start + action.target] = "1"
        pat[lay.held_pos] = BLOCK_NAMES[x].lower()
    return "".join(pat)


def add_delete_rule(action, n: int) -> tuple[str, str]:
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


def generate_rules(n: int) -> list[Classifier]:
    """All R-classifiers for n blocks: the preconditions, then the add-delete rules."""
    check_n(n)
    assert BLOCK_FIELD >= n
    actions = all_actions(n)
    pre = [Classifier(R, precondition_condition(a, n), format_action_message(a, n)) for a in actions]
    post = [Classifier(R, *add_delete_rule(a, n)) for a in actions]
    return pre + post


def load_paper_rules() -> list[Classifier]:
    """The 36 R-classifiers of the paper (n=3), read from the packaged asset."""
    from csql_sim.rulebase import loads  # local: rulebase imports this module's neighbours

    text = resources.files("csql_sim").joinpath("assets", "rules", ASSET).read_text(encoding="utf-8")
    return list(loads(text, source=ASSET).classifiers)


@functools.cache
def _rule_strings(n: int) -> tuple[tuple[str, str], ...]:
    rules = load_paper_rules() if n == 3 else generate_rules(n)
    return tuple((c.condition, c.action) for c in rules)


def r_classifiers(n: int) -> list[Classifier]:
    """Fresh R-classifier objects for n blocks (the asset for n=3, generated otherwise)."""
    return [Classifier(R, cond, act) for cond, act in _rule_strings(n)]


def domain_knowledge(n: int) -> ClassifierList:
    """A classifier list holding just the R-classifiers for n blocks."""
    return ClassifierList(r_classifiers(n))
