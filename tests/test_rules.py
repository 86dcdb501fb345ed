import re
from pathlib import Path

import pytest

from csql_sim.classifiers import apply_output, matches
from csql_sim.messages import action_code, format_action_message, format_state_message, layout
from csql_sim.rules import domain_knowledge, generate_rules, load_paper_rules
from csql_sim.world import BlocksWorld, all_actions

# Figure 5, as restored in encoding.md: (precondition, add-delete condition, output).
PAPER = [
    ("S#1#####b#####0#", "S1##############", "S001####0#####a#"),
    ("S#1#####c#####0#", "S2##############", "S00#1###0#####a#"),
    ("S##1#####a####0#", "S3##############", "S010#####0####b#"),
    ("S##1#####c####0#", "S4##############", "S0#01####0####b#"),
    ("S###1#####a###0#", "S5##############", "S01#0#####0###c#"),
    ("S###1#####b###0#", "S6##############", "S0#10#####0###c#"),
    ("S#1#####t#####0#", "S7##############", "S00#####0#####a#"),
    ("S##1#####t####0#", "S8##############", "S0#0#####0####b#"),
    ("S###1#####t###0#", "S9##############", "S0##0#####0###c#"),
    ("S#############a#", "SA##############", "S01#####t#####0#"),
    ("S#############b#", "SB##############", "S0#1#####t####0#"),
    ("S#############c#", "SC##############", "S0##1#####t###0#"),
    ("S##1##########a#", "SD##############", "S010####b#####0#"),
    ("S###1#########a#", "SE##############", "S01#0###c#####0#"),
    ("S#1###########b#", "SF##############", "S001#####a####0#"),
    ("S###1#########b#", "SG##############", "S0#10####c####0#"),
    ("S#1###########c#", "SH##############", "S00#1#####a###0#"),
    ("S##1##########c#", "SI##############", "S0#01#####b###0#"),
]
ENCODING_MD = Path(__file__).resolve().parents[1].parent / "shared" / "paper" / "encoding.md"


def test_asset_equals_paper_table():
    rules = [(c.kind, c.condition, c.action) for c in load_paper_rules()]
    acts = all_actions(3)
    expected = [("R", pre, format_action_message(acts[i], 3)) for i, (pre, _, _) in enumerate(PAPER)]
    expected += [("R", cond, out) for _, cond, out in PAPER]
    assert rules == expected


@pytest.mark.skipif(not ENCODING_MD.exists(), reason="shared/paper/encoding.md is not beside the checkout")
def test_paper_table_in_this_test_matches_encoding_md():
    text = ENCODING_MD.read_text()
    rows = [r for r in re.findall(r"^\| [1-9A-I] \|.*$", text, re.M) if r.count("|") == 6]
    found = [tuple(c.strip().strip("`") for c in r.strip("|").split("|"))[2:] for r in rows]
    assert found == PAPER


def test_generated_rules_reproduce_the_paper_for_n3():
    assert [(c.condition, c.action) for c in generate_rules(3)] == [
        (c.condition, c.action) for c in load_paper_rules()
    ]


@pytest.mark.parametrize("n", [3, 4])
def test_preconditions_give_exactly_the_legal_actions(n):
    world = BlocksWorld.of(n)
    rules = generate_rules(n) if n != 3 else load_paper_rules()
    pre = [c for c in rules if c.action[0] == "A"]
    for s_idx, state in enumerate(world.states):
        msg = format_state_message(state, s_idx)
        got = sorted(c.action for c in pre if matches(c.condition, msg))
        want = sorted(format_action_message(world.actions[a], n) for a in world.legal[s_idx])
        assert got == want, state.notation()


@pytest.mark.parametrize("n", [3, 4])
def test_add_delete_rules_give_exactly_the_successor(n):
    world = BlocksWorld.of(n)
    rules = generate_rules(n) if n != 3 else load_paper_rules()
    post = [c for c in rules if c.action[0] == "S"]
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
            assert apply_output(active[0].action, posted) == format_state_message(nxt, goal)
            checked += 1
    if n == 3:
        assert checked == 42


def test_domain_knowledge_uses_the_index():
    kb = domain_knowledge(3)
    msg = "S0111000ttt0000C"
    assert [c.action for c in kb.preconditions(msg)] == [
        "A70000001000at00", "A80000001000bt00", "A90000001000ct00",
    ]
    assert kb.predict("S7111000ttt0000C") == "S00110000tt000aC"
