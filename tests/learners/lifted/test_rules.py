"""The sweeps of LQ-CS over its lifted rules: which feature a split chooses, and when siblings merge."""

import numpy as np

from csql_sim.learners.lifted.rules import Rule, generalize_once, specialize, split_position


def rule_with(rows: list[list[int]], advantages: list[float], literals: tuple = ()) -> Rule:
    """A rule of width len(rows[0]) that learned these advantages on these feature rows."""
    rule = Rule(literals, "table", len(rows[0]))
    for a in advantages:
        rule.update(a, 0.02)
    rule.add_stats(np.array(advantages), np.array(rows, np.uint8))
    return rule


def test_the_split_takes_the_largest_gap_not_the_broadest_explanation():
    # feature 0 halves the moves with a gap of 0.6; feature 1 isolates 10 moves that cost 1 more
    rows = [[i % 2, int(i < 10)] for i in range(200)]
    adv = [(0.6 if r[0] else 0.0) + (1.0 if r[1] else 0.0) for r in rows]
    rule = rule_with(rows, adv)
    s0, c0, s1, c1 = rule.stats
    gain = c0 * c1 / (c0 + c1) * (s0 / c0 - s1 / c1) ** 2
    assert gain[0] > gain[1]  # the broad feature explains more of the spread ...
    assert split_position(rule, 0.05, 10) == 1  # ... the decisive one is chosen
    assert split_position(rule, 0.05, 11) == 0  # feature 1 lacks 11 updates on its rare side


def test_a_rare_split_needs_its_own_floor_and_a_gap_above_rare_gap():
    # feature 0 is 1 on 25 of 300 moves, which cost 2 more (a well-placed block taken off); feature 1 on
    # 25 others, which cost 0.5 more
    rows = [[int(i < 25), int(25 <= i < 50)] for i in range(300)]
    rule = rule_with(rows, [2.0 * r[0] + 0.5 * r[1] for r in rows])
    assert split_position(rule, 0.05, 100) is None  # neither rare side has 100 updates
    assert split_position(rule, 0.05, 100, rare_experience=20, rare_gap=1.0) == 0
    assert split_position(rule, 0.05, 100, rare_experience=30, rare_gap=1.0) is None  # 25 < 30
    assert split_position(rule, 0.05, 100, rare_experience=20, rare_gap=2.5) is None  # a gap of 2 is not enough
    only_small = rule_with(rows, [0.5 * r[1] for r in rows])
    assert split_position(only_small, 0.05, 100, rare_experience=20, rare_gap=1.0) is None  # 0.5 < rare_gap


def test_no_split_within_tau_or_on_a_fixed_position():
    rows = [[i % 2, i % 3 == 0] for i in range(120)]
    assert split_position(rule_with(rows, [0.01 * r[0] for r in rows]), 0.05, 10) is None
    fixed = rule_with(rows, [float(r[0]) for r in rows], literals=((0, 1),))
    assert split_position(fixed, 0.05, 10) != 0


def test_a_split_gives_two_children_with_the_sides_means_and_counts():
    rows = [[i % 2] for i in range(100)]
    rule = rule_with(rows, [1.0 if r[0] else 0.0 for r in rows])
    out, splits = specialize([rule], 0.05, 10)
    assert splits == 1
    assert [(c.literals, c.advantage, c.experience) for c in out] == [(((0, 0),), 0.0, 50), (((0, 1),), 1.0, 50)]


def test_siblings_that_agree_merge_and_those_that_differ_do_not():
    a, b = Rule(((0, 0),), "block", 2, 0.30, 0.0, 40), Rule(((0, 1),), "block", 2, 0.31, 0.0, 60)
    merged = generalize_once([a, b], 0.05, 30)
    assert merged is not None and merged[0].literals == () and merged[0].experience == 100
    assert abs(merged[0].advantage - (0.30 * 40 + 0.31 * 60) / 100) < 1e-12
    assert generalize_once([a, Rule(((0, 1),), "block", 2, 0.40, 0.0, 60)], 0.05, 30) is None
    assert generalize_once([a, Rule(((0, 1),), "block", 2, 0.31, 0.0, 20)], 0.05, 30) is None
