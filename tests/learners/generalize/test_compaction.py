"""Offline compaction: a trained rule base as a small default hierarchy, every pair still optimal (BFS)."""

import pytest

from csql_sim.core.model.search import count_optimal_greedy
from csql_sim.core.policies.default_hierarchy import DefaultHierarchy
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.core.policies.rollout import check_all_pairs
from csql_sim.core.state.goal_message import GoalForm
from csql_sim.learners.generalize.compaction import compact, greedy_sets
from csql_sim.learners.training.tabular import train


@pytest.fixture(scope="module")
def trained3():
    return train("cs-ql", seed=0, n=3, engine="reference")


def test_n3_compacted_base_is_small_and_optimal_everywhere(trained3):
    qs, facts = compact(trained3)
    assert len(qs) <= 40 and facts["pairs_decided"] == 462
    hierarchy = DefaultHierarchy(GoalForm(3), qs)
    plans = check_all_pairs(hierarchy, 3)  # the match set and first-classifier rule, pair by pair
    assert len(plans) == 462 and all(p.optimal for p in plans)  # lengths against BFS
    assert count_optimal_greedy(hierarchy.decisions().best, 3) == 462
    assert sum(hierarchy.coverage()) == 462 and min(hierarchy.coverage()) > 0  # no rule is dead


def test_plain_goal_form_without_detectors_also_plans_optimally(trained3):
    qs, _ = compact(trained3, GoalForm(3, ()))
    best = DefaultHierarchy(GoalForm(3, ()), qs).decisions().best
    assert count_optimal_greedy(best, 3) == 462
    assert len(qs) < 462


def test_compaction_follows_the_input_not_bfs(trained3):
    # keep only the Q-classifiers of goal 0: every other pair is left open (undecided)
    from csql_sim.core.files.rulebase import RuleBase

    goal0 = [c for c in trained3.classifiers if c.kind == "R" or c.condition.endswith("0")]
    rb = RuleBase(3, goal0, dict(trained3.meta))
    allowed, _ = greedy_sets(rb)
    qs, facts = compact(rb)
    assert facts["pairs_decided"] == 21 == int(allowed.any(axis=1).sum())
    table = GreedyTable(3, DefaultHierarchy(GoalForm(3), qs).decisions().best)
    assert all(table.action_index(s, 0) >= 0 for s in range(1, 22))


@pytest.mark.slow
def test_n4_compacted_base_is_at_most_200_and_optimal_everywhere():
    qs, facts = compact(train("cs-ql", seed=0, n=4, engine="reference"))
    assert len(qs) <= 200 and facts["pairs_decided"] == 15_500
    assert count_optimal_greedy(DefaultHierarchy(GoalForm(4), qs).decisions().best, 4) == 15_500
