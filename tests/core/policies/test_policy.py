import pytest

from csql_sim.core.classifiers.classifier_list import ClassifierList
from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.model.search import BfsPolicy, optimal_actions
from csql_sim.core.policies.policy import NoRuleError, QPolicy
from csql_sim.core.policies.rollout import check_all_pairs, rollout
from csql_sim.core.state.message import format_action_message, format_state_message
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import BlocksWorld, all_actions


def _optimal_q_classifiers(n: int) -> ClassifierList:
    """One Q-classifier per (state, goal): the optimal action, plus a worse rival."""
    world = BlocksWorld.of(n)
    cl = ClassifierList()
    for g, goal in enumerate(world.states):
        for s in world.states:
            if s == goal:
                continue
            best = optimal_actions(s, goal)[0]
            msg = format_state_message(s, g)
            cl.add(QClassifier(msg, format_action_message(best, n), q=0.9))
            for a in world.legal[world.state_index(s)]:
                if world.actions[a] != best:
                    cl.add(QClassifier(msg, format_action_message(world.actions[a], n), q=0.1))
    return cl


def test_greedy_policy_over_optimal_classifiers_is_optimal():
    results = check_all_pairs(QPolicy(_optimal_q_classifiers(3), 3), 3)
    assert len(results) == 462 and all(r.optimal for r in results)


def test_bfs_policy_all_pairs():
    assert all(r.optimal for r in check_all_pairs(BfsPolicy(), 3))


def test_missing_state_names_it():
    policy = QPolicy(ClassifierList(), 3)
    with pytest.raises(NoRuleError, match="S0100000bct0000C"):
        policy.act(parse_config("CBA"), parse_config("BAC"))
    r = rollout(policy, parse_config("CBA"), parse_config("BAC"))
    assert not r.reached and "S0100000bct0000C" in r.reason


def test_loop_detected():
    # Two classifiers that bounce between A,B,C and B,C+A forever.
    g = BlocksWorld.of(3).state_index(parse_config("BAC"))
    acts = all_actions(3)
    cl = ClassifierList([
        QClassifier(format_state_message(parse_config("A,B,C"), g), format_action_message(acts[6], 3), q=1),
        QClassifier(format_state_message(parse_config("B,C+A"), g), format_action_message(acts[9], 3), q=1),
    ])
    r = rollout(QPolicy(cl, 3), parse_config("A,B,C"), parse_config("BAC"))
    assert not r.reached and "loop" in r.reason


def test_illegal_greedy_action_is_a_failed_rollout():
    # A look-up table can prefer an illegal action; the rollout reports it, not a crash.
    g = BlocksWorld.of(3).state_index(parse_config("BAC"))
    acts = all_actions(3)
    cl = ClassifierList([
        QClassifier(format_state_message(parse_config("CBA"), g), format_action_message(acts[12], 3), q=1),
    ])
    r = rollout(QPolicy(cl, 3), parse_config("CBA"), parse_config("BAC"))
    assert not r.reached and "illegal action stack(A,B)" in r.reason
