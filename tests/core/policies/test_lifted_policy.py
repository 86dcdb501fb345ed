"""Lifted Q-classifiers: the file read back, hostile files refused, the shipped rules plan at any n."""

import json
from pathlib import Path

import numpy as np
import pytest

from csql_sim.core.files.kinds import LIFTED, read_rule_file
from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model.task_draws import tall_towers
from csql_sim.core.policies.lifted_classifier import LiftedPolicyError, LiftedQClassifier, most_specific, parse_lifted_q
from csql_sim.core.policies.lifted_policy import (
    LiftedPolicy,
    dumps_lifted_policy,
    load_lifted_policy,
    loads_lifted_policy,
)
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.atom_names import ATOMS
from csql_sim.core.state.move_relations import MoveRelations
from csql_sim.core.state.state_count import sample_pairs, state_count, unrank_state

SHIPPED = Path(__file__).resolve().parents[3] / "assets" / "rules" / "lifted.json"


def test_a_classifier_line_reads_back_and_says_itself_in_words():
    c = LiftedQClassifier("1110#1#0#", "table", 0.007, 0.015, 4743)
    assert parse_lifted_q(c.text()) == c
    assert c.words(ATOMS) == ("move ?x to the table if misplaced(?x) and goal-on(?x,?d) and ready(?d) and "
                         "not deadlocked(?x) and least-stuck(?x) and not holding")
    assert c.matches((1, 1, 1, 0, 0, 1, 1, 0, 0), "table") and not c.matches((1, 1, 1, 0, 0, 1, 1, 0, 0), "block")


def test_the_most_specific_matching_classifier_decides():
    general = LiftedQClassifier("1########", "table", 1.0)
    exception = LiftedQClassifier("1#####1##", "table", 0.0)
    assert most_specific([general, exception], (1, 0, 0, 0, 0, 0, 1, 0, 1), "table") is exception
    assert most_specific([general, exception], (1, 0, 0, 0, 0, 0, 0, 1, 0), "table") is general
    assert most_specific([general, exception], (0, 0, 0, 0, 0, 0, 0, 0, 0), "table") is None


def test_the_file_round_trips_and_is_recognised(tmp_path):
    classifiers = [LiftedQClassifier("1110#####", "block"), LiftedQClassifier("1########", "table", 1.0, 0.5, 3)]
    path = tmp_path / "l.json"
    path.write_text(dumps_lifted_policy(classifiers, {"seed": 4}))
    policy = load_lifted_policy(path)
    assert policy.classifiers == tuple(classifiers) and policy.meta == {"seed": 4}
    assert read_rule_file(path).kind == LIFTED and isinstance(load_policy(path, 12), LiftedPolicy)


def test_a_file_of_the_first_seven_atoms_reads_with_either_value_of_holding_and_cover():
    old = json.loads(_doc(atoms=list(ATOMS[:7]),
                          classifiers=["Q 1110#1# move(?x,?d)->table  advantage=0.250 error=0.000 experience=9"]))
    policy = loads_lifted_policy(json.dumps(old), "old.json")
    assert policy.classifiers == (LiftedQClassifier("1110#1###", "table", 0.25, 0.0, 9),)
    assert all(policy.classifiers[0].matches((1, 1, 1, 0, 1, 1, 0, held, cover), "table")
               for held in (0, 1) for cover in (0, 1))


def test_a_file_of_the_first_eight_atoms_reads_with_either_value_of_cover():
    old = json.loads(_doc(atoms=list(ATOMS[:8]),
                          classifiers=["Q 1011##10 move(?x,?d)->table  advantage=0.500 error=0.000 experience=9"]))
    policy = loads_lifted_policy(json.dumps(old), "old.json")
    assert policy.classifiers == (LiftedQClassifier("1011##10#", "table", 0.5, 0.0, 9),)


def _doc(**change):
    doc = json.loads(dumps_lifted_policy([LiftedQClassifier("1########", "table")], {}))
    doc.update(change)
    return json.dumps(doc)


@pytest.mark.parametrize(("text", "names"), [
    ("not json", "is not JSON"),
    ('{"format": "csql-sim rule base"}', "is not a csql-sim lifted q-classifiers file"),
    (_doc(version=2), "has version 2"),
    (_doc(atoms=["misplaced(?x)"]), "names other atoms"),
    (_doc(classifiers=[]), "holds 0 classifiers"),
    (_doc(classifiers=["Q 1111 move(?x,?d)->table  advantage=0 error=0 experience=1"]),
     "has 4 atoms, the file names 9"),
    (_doc(classifiers=["Q 1######## move(?x,?d)->sky  advantage=0 error=0 experience=1"]), "expected 'Q <condition>"),
    (_doc(classifiers=["Q 1######## move(?x,?d)->table  advantage=nan error=0 experience=1"]),
     "expected 'Q <condition>"),
    (_doc(atoms=list(ATOMS[:6])), "names other atoms"),
    (_doc(meta=[1]), "'meta' an object"),
])
def test_bad_files_are_refused_in_one_line_naming_what_is_wrong(text, names):
    with pytest.raises(LiftedPolicyError) as exc:
        loads_lifted_policy(text, "f.json")
    assert names in str(exc.value) and "\n" not in str(exc.value)


def test_shipped_rules_are_learned_compact_and_documented():
    policy = load_lifted_policy(SHIPPED)
    assert len(policy.classifiers) < 50
    assert policy.meta["method"] == "lq-cs" and policy.meta["params"]["sizes"] == [5]
    assert len(ATOMS) == len(policy.classifiers[0].condition)


def test_shipped_rules_plan_optimally_for_every_pair_of_three_blocks():
    policy = load_lifted_policy(SHIPPED)
    states = [unrank_state(r, 3) for r in range(state_count(3))]
    for start in states:
        for goal in states:
            run = rollout_relational(policy, start, goal)
            assert run.reached and run.length == optimal_length(start, goal), (start, goal)


@pytest.mark.parametrize("n", [10, 26])
def test_shipped_rules_solve_a_seeded_sample_of_large_worlds(n):
    policy = load_lifted_policy(SHIPPED)
    for start, goal in sample_pairs(n, 15, np.random.default_rng(n)):
        run = rollout_relational(policy, start, goal)
        assert run.reached, (start, goal, run.reason)
        assert run.length >= optimal_length(start, goal)


@pytest.mark.slow
def test_shipped_rules_are_within_half_a_percent_of_the_optimum_on_tall_towers_of_26_blocks():
    # the eight-atom rules, before cover(?x), needed 1.3% more than the optimum on these tasks
    policy, rng = load_lifted_policy(SHIPPED), np.random.default_rng(0)
    cost = optimum = 0
    for _ in range(20):
        start, goal = tall_towers(26, rng), tall_towers(26, rng)
        run = rollout_relational(policy, start, goal)
        assert run.reached, (start, goal, run.reason)
        cost, optimum = cost + run.length, optimum + optimal_length(start, goal)
    assert cost <= 1.005 * optimum, (cost, optimum)


class _FromScratch(LiftedPolicy):
    """The policy as it was: every relation of every state computed from scratch."""

    def relations(self, state, target):
        return MoveRelations(state, target)


def test_incremental_relations_give_the_same_plans_as_from_scratch_ones():
    policy = load_lifted_policy(SHIPPED)
    scratch = _FromScratch(policy.classifiers)
    rng = np.random.default_rng(7)
    lengths = []
    for n in (7, 9, 12, 16):
        for start, goal in sample_pairs(n, 8, rng):
            got, want = rollout_relational(policy, start, goal), rollout_relational(scratch, start, goal)
            assert got == want, (start.notation(), goal.notation())
            lengths.append(len(got.actions))
    assert min(lengths) > 0
