import pytest

from csql_sim.classifiers import Classifier, ClassifierList, Q, R, apply_output, matches
from csql_sim.messages import format_state_message
from csql_sim.rules import generate_rules
from csql_sim.world import BlocksWorld


def test_matching_and_output():
    assert matches("S#1#", "S01x")
    assert not matches("S#1#", "S00x")
    assert not matches("S#1#", "S01")
    assert apply_output("S0#1", "S7ab") == "S0a1"


@pytest.mark.parametrize("n", [3, 4])
def test_index_agrees_with_brute_force_on_every_state(n):
    rules = generate_rules(n)
    cl = ClassifierList(rules)
    world = BlocksWorld.of(n)
    for i, s in enumerate(world.states):
        msg = format_state_message(s, i)
        brute = [c for c in rules if matches(c.condition, msg)]
        assert sorted(id(c) for c in cl.match(msg)) == sorted(id(c) for c in brute)


def test_r_and_q_live_in_one_list():
    cl = ClassifierList(generate_rules(3))
    msg = "S0111000ttt0000C"
    acts = [c.action for c in cl.preconditions(msg)]
    made = cl.cover(msg, acts, q=0.0)
    assert len(made) == 3 and len(cl) == 36 + 3
    again = cl.cover(msg, acts, q=0.5)
    assert len(cl) == 39 and all(c.q == 0.0 for c in again.values())
    kinds = {c.kind for c in cl}
    assert kinds == {R, Q}
    matched = cl.match(msg)
    assert sum(c.kind == Q for c in matched) == 3 and sum(c.kind == R for c in matched) == 3


def test_remove_if_keeps_index_consistent():
    cl = ClassifierList(generate_rules(3))
    cl.add(Classifier(Q, "S0111000ttt0000C", "A70000001000at00", q=1.0, strength=0.05))
    cl.add(Classifier(Q, "S0111000ttt0000C", "A80000001000bt00", q=1.0, strength=0.9))
    removed = cl.remove_if(lambda c: c.kind == Q and c.strength < 0.1)
    assert removed == 1
    assert list(cl.q_for("S0111000ttt0000C")) == ["A80000001000bt00"]
    assert len(cl.preconditions("S0111000ttt0000C")) == 3


def test_predict_requires_one_rule():
    cl = ClassifierList(generate_rules(3))
    with pytest.raises(KeyError):
        cl.predict("S0111000ttt0000C")  # empty action slot: no add-delete rule
