import pytest

from csql_sim.core.classifiers.r_classifier import generate_rules, load_paper_rules
from csql_sim.core.state.message import format_action_message, format_state_message, layout
from csql_sim.core.state.notation import parse_action_name, parse_config
from csql_sim.discovery.explore import exhaustive_transitions
from csql_sim.discovery.induction import (
    Evidence,
    Experience,
    Reliability,
    disturbance,
    induce_action,
    induce_rules,
)


def strings(rules):
    return [(r.condition, r.action) for r in rules]


def test_symbolic_transitions_give_figure_5_string_for_string():
    assert strings(induce_rules(exhaustive_transitions(3), 3)) == strings(load_paper_rules())


def test_four_blocks_give_the_64_generated_rules():
    got = induce_rules(exhaustive_transitions(4, repeats=3), 4)
    assert len(got) == 64
    assert strings(got) == strings(generate_rules(4))


def test_too_few_successes_make_no_rule():
    rel = Reliability(min_successes=3)
    once = exhaustive_transitions(3, repeats=1)  # unstack(A,B) succeeds in only two states
    rules = induce_rules(once, 3, rel)
    assert "A10000001000ab00" not in {r.action for r in rules}


def _transition(before, action, after, ok):
    n = 3
    act = parse_action_name(action, n)
    return Experience(format_state_message(parse_config(before, n), 0), format_action_message(act, n),
                      format_state_message(parse_config(after, n), 0), ok)


def test_a_knocked_over_tower_creates_no_rule():
    # stack(C,B) "succeeded" but the tower B-on-A was knocked over: every cube on the table
    noisy = [_transition("AB+C", "stack(C,B)", "A,B,C", True)]
    rules = induce_rules(exhaustive_transitions(3) + noisy, 3)
    assert strings(rules) == strings(load_paper_rules())
    alone = induce_rules(noisy * 2, 3)
    assert alone == []  # two odd observations are below the reliability threshold


def test_noise_among_many_successes_does_not_change_the_rule():
    clean = exhaustive_transitions(3, repeats=6)
    noisy = [_transition("AB,C", "pickup(C)", "A,B+C", True)]  # B knocked off A meanwhile
    ev = Evidence(3)
    for t in clean + noisy:
        ev.add(t)
    code = format_action_message(parse_action_name("pickup(C)", 3), 3)
    got = induce_action(ev, code)
    assert (got.add_delete.condition, got.add_delete.action) == ("S9##############", "S0##0#####0###c#")


def test_a_legal_state_with_a_missed_grasp_stays_a_success_state():
    missed = [_transition("A,B,C", "pickup(A)", "A,B,C", False)]
    assert strings(induce_rules(exhaustive_transitions(3) + missed, 3)) == strings(load_paper_rules())


def test_inconsistent_evidence_makes_no_precondition():
    # pickup(A) refused (nothing changing) as often as it succeeded in every state where it is legal
    legal = [t for t in exhaustive_transitions(3) if t.action == "A70000001000at00" and t.ok]
    refused = [Experience(t.before, t.action, t.before, False) for t in legal]
    rules = induce_rules(legal + refused, 3)
    assert any(r.condition == "S7##############" for r in rules)  # the effect is consistent ...
    assert all(r.action != "A70000001000at00" for r in rules)


@pytest.mark.parametrize("n", [2])
def test_two_blocks_give_equivalent_shorter_conditions(n):
    from csql_sim.core.classifiers.r_classifier import matches
    from csql_sim.core.state.world import all_actions, all_states, is_legal

    rules = {r.action: r.condition for r in induce_rules(exhaustive_transitions(n), n) if r.action[0] == "A"}
    for s in all_states(n):
        msg = format_state_message(s, 0)
        for a in all_actions(n):
            assert matches(rules[format_action_message(a, n)], msg) == is_legal(s, a)


def test_failures_after_moving_are_not_negative_evidence():
    # pickup(A) legal in "A,B,C" but the grasp missed there again and again (a cube askew)
    missed = [Experience(t.before, t.action, t.before, False, "grasp of A missed", refused=False)
              for t in exhaustive_transitions(3, repeats=1)
              if t.ok and t.action == "A70000001000at00" and t.before == "S0111000ttt00000"] * 20
    assert missed
    assert strings(induce_rules(exhaustive_transitions(3) + missed, 3)) == strings(load_paper_rules())
    as_refusals = [Experience(t.before, t.action, t.after, False, t.reason) for t in missed]
    rules = induce_rules(exhaustive_transitions(3) + as_refusals, 3)
    assert "A70000001000at00" not in {r.action for r in rules if r.action.startswith("A")}


def _judge(before, action, after, ok, refused=None):
    t = _transition(before, action, after, ok)
    return disturbance(Experience(t.before, t.action, t.after, ok, "", refused), layout(3))


def test_outcomes_the_action_did_not_cause_are_disturbed():
    assert _judge("A,B,C", "pickup(A)", "B,C+A", True) == ""  # what pickup(A) does
    assert _judge("AB,C", "pickup(C)", "AB,C", False) == ""  # refused, nothing changed
    assert _judge("CBA", "unstack(C,B)", "A,B+C", True)  # B fell off A: B is not the moved cube
    assert _judge("AB,C", "pickup(B)", "A,B,C", False)  # refused, yet A came off B
    assert _judge("A,B+C", "stack(C,B)", "A,B,C", True)  # a successful stack left C on the table
    assert _judge("AB,C", "unstack(A,B)", "A,B,C", True)  # a successful pick and an empty hand
    assert _judge("AB,C", "unstack(A,B)", "A,B,C", False, refused=False) == ""  # a failed motion: not judged


def test_disturbed_transitions_count_for_neither_side():
    knocked = [_transition("CBA", "unstack(C,B)", "A,B+C", True)] * 5  # the arm knocked B off A each time
    ev = Evidence(3)
    for t in knocked:
        assert ev.add(t)
    assert ev.disturbed == 5 and not ev.effects and not ev.outcomes
    rules = induce_rules(exhaustive_transitions(3, repeats=1) + knocked * 3 + exhaustive_transitions(3, repeats=2), 3)
    assert strings(rules) == strings(load_paper_rules())
