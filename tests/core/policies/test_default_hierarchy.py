"""The default hierarchy: match set, first classifier acts; one-by-one and all-pairs answers agree."""

import pytest

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.policies.default_hierarchy import DefaultHierarchy
from csql_sim.core.policies.policy import NoRuleError
from csql_sim.core.state.goal_message import GoalForm
from csql_sim.core.state.message import action_messages
from csql_sim.core.state.notation import parse_state_arg
from csql_sim.core.state.world import BlocksWorld
from csql_sim.infra.errors import CsqlError

FORM = GoalForm(3)
ANY = "S" + "#" * 14 + "G" + "#" * 25


def _q(condition, action_name):
    world = BlocksWorld.of(3)
    k = next(i for i, a in enumerate(world.actions) if a.name() == action_name)
    return QClassifier(condition, action_messages(3)[k])


def test_first_matching_candidate_acts():
    # putdown(A) first, but it is no candidate with the hand empty: the pickup acts
    rules = [_q(ANY, "putdown(A)"), _q(ANY, "pickup(A)"), _q(ANY, "pickup(B)")]
    h = DefaultHierarchy(FORM, rules)
    start, goal = parse_state_arg("A,B,C", 3), parse_state_arg("AB,C", 3)
    assert h.act(start, goal).name() == "pickup(A)"
    assert [c.action for c in h.match_set(start, goal)] == [rules[1].action, rules[2].action]
    assert h.act(goal, goal) is None


def test_empty_match_set_is_an_error_naming_the_message():
    h = DefaultHierarchy(FORM, [_q(ANY, "putdown(A)")])
    with pytest.raises(NoRuleError, match="S0111000ttt0000G"):
        h.act(parse_state_arg("A,B,C", 3), parse_state_arg("AB,C", 3))


def test_all_pairs_agree_with_act_and_coverage_counts_decisions():
    rules = [_q("S" + "#" * 14 + "G" + "#" * 12 + "0" + "#" * 12, "pickup(A)"), _q(ANY, "putdown(B)"),
             _q(ANY, "unstack(C,B)"), _q(ANY, "pickup(C)")]
    h = DefaultHierarchy(FORM, rules)
    world = h.world
    d = h.decisions()
    count = len(world.states)
    for s, state in enumerate(world.states):
        for g, goal in enumerate(world.states):
            try:
                action = h.act(state, goal)
            except NoRuleError:
                action = None
            want = -1 if action is None else world.action_index(action)
            assert d.best[s * count + g] == want
    assert sum(h.coverage()) == int((d.rule >= 0).sum())


def test_conditions_are_checked():
    with pytest.raises(CsqlError, match="position 16"):
        DefaultHierarchy(FORM, [_q("S" + "#" * 14 + "Gx" + "#" * 24, "pickup(A)")])


@pytest.mark.parametrize("suffix", [".yaml", ".npz"])
def test_goal_form_rule_files_round_trip_and_refuse_bad_conditions(tmp_path, suffix):
    from csql_sim.core.files.rulebase import RuleBase, RuleBaseError, load, save

    rules = [_q("S" + "#" * 14 + "G" + "#" * 12 + "0" + "#" * 12, "pickup(A)"), _q(ANY, "putdown(B)")]
    path = save(tmp_path / f"g{suffix}", RuleBase(3, rules, FORM.meta()))
    back = load(path)
    assert [(c.condition, c.action) for c in back.classifiers] == [(c.condition, c.action) for c in rules]
    assert DefaultHierarchy.from_rulebase(back).decisions().best.tolist() == \
        DefaultHierarchy(FORM, rules).decisions().best.tolist()
    bad = RuleBase(3, [_q("S" + "#" * 14 + "Gz" + "#" * 24, "pickup(A)")], FORM.meta())
    save(tmp_path / f"bad{suffix}", bad)
    with pytest.raises(RuleBaseError, match="position 16"):
        load(tmp_path / f"bad{suffix}")
    with pytest.raises(CsqlError, match="meta.form"):  # refused on writing (npz) or reading (YAML)
        save(tmp_path / f"odd{suffix}", RuleBase(3, rules, {"form": "distances"}))
        load(tmp_path / f"odd{suffix}")
