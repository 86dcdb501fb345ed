import pytest

from csql_sim.core.classifiers.lifted_rule import BLOCKS_WORLD, ground_rules
from csql_sim.core.classifiers.r_classifier import AddDeleteRule, PreconditionRule, r_classifiers
from csql_sim.discovery.lifting import lift_rule, lift_rules
from csql_sim.jobs.discover import discover


def strings(rules):
    return [(r.condition, r.action) for r in rules]


@pytest.fixture(scope="module")
def lifted_at_three():
    return lift_rules(discover(3, "symbolic", seed=1).rules, 3)


def test_discovery_at_three_blocks_lifts_to_the_four_schemas(lifted_at_three):
    assert lifted_at_three.problems == {}
    assert lifted_at_three.rules == list(BLOCKS_WORLD)


@pytest.mark.parametrize("n", [4, 5, 6])
def test_lifted_rules_discovered_at_three_ground_to_the_generated_rules(lifted_at_three, n):
    assert strings(ground_rules(lifted_at_three.rules, n)) == strings(r_classifiers(n))


def test_a_rule_about_a_third_block_is_not_lifted():
    rule = PreconditionRule("S#1#####bt####0#", "A10000001000ab00")  # unstack(A,B) also asks B on the table
    assert lift_rule(rule, 3).rule is not None
    rule = PreconditionRule("S#1#####b#t###0#", "A10000001000ab00")  # ... and C on the table
    assert lift_rule(rule, 3).rule is None


def test_a_schema_with_disagreeing_instances_is_reported_not_lifted():
    rules = list(r_classifiers(3))
    rules[0] = PreconditionRule("S#1#####b#####0#".replace("0#", "##"), rules[0].action)  # drop held=0 for one
    out = lift_rules(rules, 3)
    assert "precondition unstack" in out.problems and len(out.rules) == 7


def test_a_missing_instance_is_reported():
    rules = [r for r in r_classifiers(3) if not (isinstance(r, AddDeleteRule) and r.condition.startswith("SA"))]
    out = lift_rules(rules, 3)
    assert list(out.problems) == ["add-delete putdown"]


def test_two_blocks_lift_to_shorter_conditions_that_do_not_generalize():
    out = lift_rules(discover(2, "symbolic", seed=1).rules, 2)
    assert out.rules != list(BLOCKS_WORLD)
    assert strings(ground_rules(out.rules, 4)) != strings(r_classifiers(4))
