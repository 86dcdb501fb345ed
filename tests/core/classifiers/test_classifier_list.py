import pytest

from csql_sim.core.classifiers.classifier_list import ClassifierList, PatternIndex
from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import AddDeleteRule, PreconditionRule, generate_rules, matches
from csql_sim.core.state.message import format_state_message
from csql_sim.core.state.world import BlocksWorld


def test_matching_and_output():
    assert matches("S#1#", "S01x")
    assert not matches("S#1#", "S00x")
    assert not matches("S#1#", "S01")
    assert AddDeleteRule("S7##", "S0#1").apply("S7ab") == "S0a1"


@pytest.mark.parametrize("n", [3, 4])
def test_index_agrees_with_brute_force_on_every_state(n):
    rules = generate_rules(n)
    cl = ClassifierList(rules)
    index = PatternIndex(rules)
    world = BlocksWorld.of(n)
    for i, s in enumerate(world.states):
        msg = format_state_message(s, i)
        brute = [c for c in rules if matches(c.condition, msg)]
        assert cl.match(msg) == brute
        assert list(index.match(msg)) == brute


def test_r_and_q_live_in_one_list():
    cl = ClassifierList(generate_rules(3))
    msg = "S0111000ttt0000C"
    acts = [c.action for c in cl.match(msg) if isinstance(c, PreconditionRule)]
    made = cl.cover(msg, acts, q=0.0)
    assert len(made) == 3 and len(cl) == 36 + 3
    again = cl.cover(msg, acts, q=0.5)
    assert len(cl) == 39 and all(c.q == 0.0 for c in again.values())
    assert {c.kind for c in cl} == {"R", "Q"}
    assert len(cl.r_classifiers) == 36 and len(cl.q_classifiers) == 3
    matched = cl.match(msg)
    assert sum(isinstance(c, QClassifier) for c in matched) == 3
    assert sum(isinstance(c, PreconditionRule) for c in matched) == 3


def test_adding_an_r_classifier_reindexes():
    cl = ClassifierList(generate_rules(3))
    msg = "S0111000ttt0000C"
    before = len(cl.match(msg))
    cl.add(PreconditionRule("S#1#############", "A70000001000at00"))
    assert len(cl.match(msg)) == before + 1
