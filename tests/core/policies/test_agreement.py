import json
from pathlib import Path

import numpy as np

from csql_sim.cli import main
from csql_sim.core.policies.agreement import (
    AGREEMENT_SEED,
    AGREEMENT_SIZES,
    AGREEMENT_STATES,
    agreement,
    agreement_states,
    move_of,
)
from csql_sim.core.policies.gn2 import Gn2Policy
from csql_sim.core.policies.hand_ordering import hand_ordering, hand_ordering_without_cover
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.state.moves import Move
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state_count import sample_pairs

SHIPPED = Path(__file__).parents[3] / "assets" / "rules" / "lifted.json"


def test_the_sample_is_seeded_uniform_pairs_drawn_size_after_size():
    states = agreement_states()
    rng = np.random.default_rng(AGREEMENT_SEED)
    assert list(states) == list(AGREEMENT_SIZES)
    for n in AGREEMENT_SIZES:
        assert states[n] == sample_pairs(n, AGREEMENT_STATES, rng)


def test_a_move_is_the_pick_and_the_put_that_follows():
    start, goal = parse_config("AB,CD"), parse_config("AD,CB")
    assert move_of(hand_ordering(), start, goal) == Move(3, -1)  # D, the cover (B is dropped from it first)
    assert move_of(hand_ordering(), parse_config("AD,CB"), goal) is None


def test_the_hand_ordering_agrees_with_itself_and_not_with_the_ordering_without_cover():
    states = agreement_states(count=20)
    assert agreement(hand_ordering(), states).complete
    without = agreement(hand_ordering_without_cover(), states)
    assert not without.complete and 0.5 < without.share < 1
    assert sum(without.states.values()) == 60


def test_show_prints_the_shipped_files_agreement_and_it_equals_a_direct_computation(capsys, tmp_path):
    out = tmp_path / "show.json"
    assert main(["show", "--rules", str(SHIPPED)]) == 0
    text = capsys.readouterr().out
    assert main(["show", "--rules", str(SHIPPED), "--json", str(out)]) == 0
    direct = agreement(load_policy(SHIPPED))  # the same states: agreement_states()
    assert direct.describe() in text
    doc = json.loads(out.read_text())["agreement"]
    assert doc["agreed"] == {str(n): k for n, k in direct.agreed.items()}
    assert doc["share"] == direct.share == 1.0 and "a learned ranking of the given atoms" in text


def test_a_baseline_that_chooses_otherwise_is_not_called_a_ranking_of_the_given_atoms():
    found = agreement(Gn2Policy(), agreement_states(count=30))
    assert not found.complete and "learned ranking" not in found.describe()
