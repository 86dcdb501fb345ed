import re
from pathlib import Path

import pytest

from csql_sim.core.classifiers.r_classifier import (
    AddDeleteRule,
    PreconditionRule,
    generate_rules,
    load_paper_rules,
    matches,
    parse_r_classifier,
)
from csql_sim.core.state.message import action_code, format_action_message, format_state_message, layout
from csql_sim.core.state.world import BlocksWorld, all_actions

FIGURE5_TABLE = Path(__file__).parents[2] / "data" / "figure5.md"
"""encoding.md's table of Figure 5, copied verbatim into the tests so that a fresh clone checks it."""


def _paper_rows() -> list[tuple[str, str, str]]:
    """(precondition, add-delete condition, output) per action code 1-9, A-I."""
    rows = [r for r in re.findall(r"^\| [1-9A-I] \|.*$", FIGURE5_TABLE.read_text(), re.M) if r.count("|") == 6]
    return [tuple(c.strip().strip("`") for c in r.strip("|").split("|"))[2:] for r in rows]


PAPER = _paper_rows()


def test_the_papers_table_has_all_18_actions():
    assert len(PAPER) == 18
    assert PAPER[0] == ("S#1#####b#####0#", "S1##############", "S001####0#####a#")


def test_asset_equals_paper_table():
    rules = [(c.kind, c.condition, c.action) for c in load_paper_rules()]
    acts = all_actions(3)
    expected = [("R", pre, format_action_message(acts[i], 3)) for i, (pre, _, _) in enumerate(PAPER)]
    expected += [("R", cond, out) for _, cond, out in PAPER]
    assert rules == expected


def test_generated_rules_reproduce_the_paper_for_n3():
    assert [(c.condition, c.action) for c in generate_rules(3)] == [
        (c.condition, c.action) for c in load_paper_rules()
    ]


@pytest.mark.parametrize("n", [3, 4])
def test_preconditions_give_exactly_the_legal_actions(n):
    world = BlocksWorld.of(n)
    rules = generate_rules(n) if n != 3 else load_paper_rules()
    pre = [c for c in rules if isinstance(c, PreconditionRule)]
    for s_idx, state in enumerate(world.states):
        msg = format_state_message(state, s_idx)
        got = sorted(c.action for c in pre if matches(c.condition, msg))
        want = sorted(format_action_message(world.actions[a], n) for a in world.legal[s_idx])
        assert got == want, state.notation()


@pytest.mark.parametrize("n", [3, 4])
def test_add_delete_rules_give_exactly_the_successor(n):
    world = BlocksWorld.of(n)
    rules = generate_rules(n) if n != 3 else load_paper_rules()
    post = [c for c in rules if isinstance(c, AddDeleteRule)]
    aw = layout(n).action_width
    checked = 0
    for s_idx, state in enumerate(world.states):
        goal = (s_idx + 3) % len(world.states)
        for a in world.legal[s_idx]:
            code = action_code(world.actions[a], n)
            msg = format_state_message(state, goal)
            posted = msg[0] + code + msg[1 + aw :]
            active = [c for c in post if matches(c.condition, posted)]
            assert len(active) == 1
            nxt = world.states[world.next_state[s_idx][a]]
            assert active[0].apply(posted) == format_state_message(nxt, goal)
            checked += 1
    if n == 3:
        assert checked == 42


def test_rules_are_typed_records():
    rules = load_paper_rules()
    assert [type(r) for r in rules] == [PreconditionRule] * 18 + [AddDeleteRule] * 18
    assert parse_r_classifier("S7##############", "S00#####0#####a#") == rules[18 + 6]
    with pytest.raises(Exception, match="neither"):
        parse_r_classifier("S7##############", "X00#####0#####a#")
