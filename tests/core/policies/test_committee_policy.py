"""A committee of populations over generated features: ranked by mean advantage; its file read back or refused."""

import json

import numpy as np
import pytest

from csql_sim.core.features.formulation import load_formulation
from csql_sim.core.features.move_features import Literal
from csql_sim.core.policies.committee_policy import (
    COMMITTEE_VERSION,
    CommitteePolicy,
    dumps_committee,
)
from csql_sim.core.policies.feature_policy import FeaturePolicy
from csql_sim.core.policies.lifted_classifier import LiftedPolicyError, LiftedQClassifier
from csql_sim.core.policies.loader import load_policy, loads_lifted_file
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.move_relations import towards
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.infra.assets import asset_text

WELL_PLACED = "all(star(on),eq(on,on_g))"
PLACED_AFTER, PLACED, CLEAR_D = Literal(WELL_PLACED, "x'"), Literal(WELL_PLACED, "x"), Literal("clear", "d")


def member(classifiers: list[tuple[str, str, float]], literals: tuple[Literal, ...]) -> FeaturePolicy:
    """A population of the move domain from (condition, kind, advantage) triples."""
    return FeaturePolicy([LiftedQClassifier(c, k, a) for c, k, a in classifiers], literals,
                         load_formulation("move"), asset_text("domains", "blocks-move.pddl"))


def constructive_first(table: float) -> FeaturePolicy:
    """Place a block for good (0), else the table (``table``), else any other block move (2)."""
    return member([("1", "block", 0.0), ("0", "block", 2.0), ("#", "table", table)], (PLACED_AFTER,))


def test_the_committee_ranks_by_the_mean_advantage_of_its_members(tmp_path):
    """Every move of sampled 6-block pairs: the committee's order is that of the members' mean advantages."""
    a = constructive_first(1.0)
    b = member([("1", "block", 0.0), ("#", "table", 3.0), ("0", "block", 0.5)], (PLACED_AFTER,))  # table last
    committee = CommitteePolicy([a, b])
    flips = 0
    for start, goal in sample_pairs(6, 40, np.random.default_rng(1)):
        target = towards(start, goal)[0]
        options, mean = committee.advantages(start, target)
        _, first = a.advantages(start, target)
        _, second = b.advantages(start, target)
        assert mean == [(x + y) / 2 for x, y in zip(first, second, strict=True)]
        order = committee.ranked(start, target)
        assert order == sorted(options, key=lambda m: (mean[options.index(m)], options.index(m)))
        flips += a.ranked(start, target)[0] != order[0]
    assert flips > 0  # where no block can be placed, a ranks the table first and the committee a block move (1.25)


def test_a_move_some_member_does_not_match_ranks_after_every_move_all_match():
    a = constructive_first(1.0)
    b = member([("1", "block", 0.0), ("0", "block", 0.5)], (PLACED_AFTER,))  # no table classifier
    committee = CommitteePolicy([a, b])
    start, goal = sample_pairs(6, 1, np.random.default_rng(4))[0]
    options, mean = committee.advantages(start, goal)
    matched = [m for m in options if m.kind == "block"]
    table = [m for m in options if m.kind == "table"]
    ranked = committee.ranked(start, goal)
    assert table and matched and set(ranked[len(matched):]) == set(table) and set(ranked) == set(options)


def test_a_committee_of_one_plans_as_its_member(tmp_path):
    a = constructive_first(1.0)
    for start, goal in sample_pairs(8, 20, np.random.default_rng(2)):
        assert rollout_relational(CommitteePolicy([a]), start, goal, hand=False).actions == \
            rollout_relational(a, start, goal, hand=False).actions


def test_a_committee_file_reads_back_member_by_member_and_solves(tmp_path):
    a = constructive_first(1.0)
    b = member([("1##", "block", 0.0), ("0##", "block", 2.0), ("#0#", "table", 1.0), ("#1#", "table", 4.0)],
               (PLACED_AFTER, PLACED, CLEAR_D))  # CLEAR_D is tested by none: cut from the file
    path = tmp_path / "c.json"
    path.write_text(dumps_committee([(m.classifiers, m.literals) for m in (a, b)],
                                    asset_text("domains", "blocks-move.pddl"), "move", {"seed": 7}))
    doc = json.loads(path.read_text())
    assert doc["version"] == COMMITTEE_VERSION and [len(m["atoms"]) for m in doc["members"]] == [1, 2]
    policy = load_policy(path)
    assert isinstance(policy, CommitteePolicy) and policy.meta == {"seed": 7}
    assert [m.literals for m in policy.members] == [a.literals, b.literals[:2]]
    assert [c.text() for c in policy.members[0].classifiers] == [c.text() for c in a.classifiers]
    assert [c.condition for c in policy.members[1].classifiers] == ["1#", "0#", "#0", "#1"]
    assert policy.text()[0] == "member 1:" and "member 2:" in policy.text()
    for start, goal in sample_pairs(8, 20, np.random.default_rng(3)):
        assert rollout_relational(policy, start, goal, hand=False).reached


def committee_doc() -> dict:
    a = constructive_first(1.0)
    return json.loads(dumps_committee([(a.classifiers, a.literals)] * 2, asset_text("domains", "blocks-move.pddl"),
                                      "move", {}))


@pytest.mark.parametrize(("change", "named"), [
    (lambda d: d.update(members={}), "members"),
    (lambda d: d.update(members=[]), "members"),
    (lambda d: d.update(members=[d["members"][0]] * 10), "members"),
    (lambda d: d.update(members=[1, 2]), "members"),
    (lambda d: d["members"][1].update(atoms=["x:nothere"]), "member 2"),
    (lambda d: d["members"][0].pop("classifiers"), "member 1"),
    (lambda d: d.update(version=1), "members"),
    (lambda d: d.update(version=3), "version"),
    (lambda d: d.update(version=True), "version"),
])
def test_a_bad_committee_file_is_one_error_naming_what_is_wrong(change, named):
    doc = committee_doc()
    change(doc)
    with pytest.raises(LiftedPolicyError, match=named) as info:
        loads_lifted_file(json.dumps(doc), "c.json")
    assert "\n" not in str(info.value) and "c.json" in str(info.value)
