import numpy as np
import pytest

from csql_sim.core.classifiers.lifted_rule import (
    BLOCKS_WORLD,
    BLOCKS_WORLD_TEXT,
    LiftedRuleError,
    dumps_lifted,
    ground_rules,
    load_lifted,
    loads_lifted,
    parse_lifted_rule,
    parse_lifted_rules,
)
from csql_sim.core.classifiers.r_classifier import load_paper_rules, r_classifiers
from csql_sim.core.model.world_model import WorldModel


def strings(rules):
    return [(r.condition, r.action) for r in rules]


@pytest.mark.parametrize("n", [2, 3, 4, 5, 6])
def test_the_four_schemas_ground_to_the_tools_rules_string_for_string(n):
    assert strings(ground_rules(BLOCKS_WORLD, n)) == strings(r_classifiers(n))


def test_grounding_at_three_blocks_is_the_papers_figure_5():
    assert strings(ground_rules(BLOCKS_WORLD, 3)) == strings(load_paper_rules())
    assert len(BLOCKS_WORLD) == 8


def test_text_form_round_trips_and_is_canonical():
    assert [r.text() for r in BLOCKS_WORLD] == list(BLOCKS_WORLD_TEXT)
    shuffled = "R  S[held=0 on(?x)=?y clear(?x)=1]   A[unstack(?x,?y)]"
    assert parse_lifted_rule(shuffled) == BLOCKS_WORLD[0]
    assert parse_lifted_rules(["# comment", "", BLOCKS_WORLD_TEXT[2]]) == (BLOCKS_WORLD[2],)


@pytest.mark.parametrize("bad", [
    "R S[clear(?x)=1] A[pickup(?x,?y)]",  # pickup binds one variable
    "R S[clear(?z)=1] A[pickup(?x)]",  # unbound variable
    "R S[on(?x)=?x] A[unstack(?x,?y)]",  # a block on itself
    "R S[clear(?x)=2] A[pickup(?x)]",  # clear is 0 or 1
    "R S[held=0 held=0] A[pickup(?x)]",  # one field twice
    "R S[held=0] A[fly(?x)]",  # no such operator
    "R S[held=0] S[held=?x]",  # an add-delete condition is act=...
    "S#1#####b#####0# A10000001000ab00",  # a ground rule
])
def test_malformed_lifted_rules_are_refused(bad):
    with pytest.raises(LiftedRuleError):
        parse_lifted_rule(bad)


def test_lifted_rule_file_round_trips(tmp_path):
    path = tmp_path / "lifted.json"
    path.write_text(dumps_lifted(BLOCKS_WORLD, {"source": "test"}))
    assert load_lifted(path) == BLOCKS_WORLD


@pytest.mark.parametrize("text", ["not json", "[]", '{"format": "csql-sim lifted rules", "version": 9, "rules": []}',
                                  '{"format": "csql-sim lifted rules", "version": 1, "rules": [1]}',
                                  '{"format": "other", "version": 1, "rules": []}'])
def test_foreign_or_damaged_lifted_files_are_refused(text):
    with pytest.raises(LiftedRuleError):
        loads_lifted(text)


@pytest.mark.parametrize("n", [3, 4, 5])
def test_the_world_model_accepts_lifted_rules(n):
    lifted, given = WorldModel.from_lifted(BLOCKS_WORLD, n), WorldModel.for_blocks(n)
    assert np.array_equal(lifted.table.next_state, given.table.next_state)
