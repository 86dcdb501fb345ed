import itertools

import numpy as np

from csql_sim.core.policies.hand_ordering import hand_ordering, hand_ordering_without_cover, hand_rank
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.atom_names import ATOMS
from csql_sim.core.state.move_relations import MoveRelations
from csql_sim.core.state.moves import after
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state_count import sample_pairs


def bits(**held: int) -> tuple[int, ...]:
    names = ["misplaced", "goal_on", "ready", "stuck", "above", "least", "deadlock", "holding", "cover"]
    return tuple(held.get(name, 0) for name in names)


def test_the_six_ranks_in_the_issue_order():
    assert hand_rank(bits(misplaced=1, goal_on=1, ready=1), "block") == 0
    assert hand_rank(bits(misplaced=1, goal_on=1, ready=1), "table") == 0
    assert hand_rank(bits(misplaced=1, stuck=1, cover=1), "table") == 1
    assert hand_rank(bits(misplaced=1, stuck=1), "table") == 2
    assert hand_rank(bits(misplaced=1, above=1), "table") == 3
    assert hand_rank(bits(misplaced=1), "table") == 4 == hand_rank(bits(), "table")
    assert hand_rank(bits(misplaced=1, stuck=1, cover=1), "block") == 5


def test_the_policy_holds_one_classifier_per_pattern_and_kind_with_the_rank_as_advantage():
    policy = hand_ordering()
    assert len(policy.classifiers) == 2 ** len(ATOMS) * 2
    for c in policy.classifiers[:64]:
        assert c.advantage == hand_rank(tuple(map(int, c.condition)), c.kind)


def test_a_cover_block_goes_to_the_table_before_another_deadlocked_one():
    start, goal = parse_config("AB,CD"), parse_config("AD,CB")
    rel = MoveRelations(start, goal)
    ranked = sorted(rel.candidates(), key=lambda mb: hand_rank(mb[1], mb[0].kind))
    best = ranked[0]
    assert best[0].onto < 0 and best[1][8] == 1  # a table move of a cover block
    assert not MoveRelations(after(start, best[0]), goal).stuck  # one visitor breaks the deadlock


def test_the_hand_ordering_with_cover_plans_shorter_than_without_on_a_seeded_sample():
    pairs = sample_pairs(12, 20, np.random.default_rng(3))
    with_cover = [rollout_relational(hand_ordering(), s, g) for s, g in pairs]
    without = [rollout_relational(hand_ordering_without_cover(), s, g) for s, g in pairs]
    assert all(r.reached for r in itertools.chain(with_cover, without))
    assert sum(r.length for r in with_cover) < sum(r.length for r in without)
