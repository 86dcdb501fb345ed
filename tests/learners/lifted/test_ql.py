"""LQ-CS: lifted Q-classifiers learned from an empty population on small worlds."""

import json
from pathlib import Path

import numpy as np
import pytest

from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model.task_draws import tall_towers
from csql_sim.core.policies.lifted_policy import load_lifted_policy
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.atom_names import ATOMS
from csql_sim.core.state.state_count import sample_pairs, state_count, unrank_state
from csql_sim.learners.lifted.params import LiftedParams
from csql_sim.learners.lifted.ql import train_lifted
from csql_sim.learners.paper.params import ParamsError

SHIPPED = Path(__file__).resolve().parents[3] / "assets" / "rules" / "lifted.json"


@pytest.mark.parametrize("change", [{"trials": 0}, {"sizes": (6,)}, {"sizes": ()}, {"beta": 0.0}, {"epsilon": 1.0},
                                    {"tau": float("inf")}, {"goals": 0}, {"min_experience": 0}, {"sweep": 0},
                                    {"replay": 1}, {"early": 1.0}, {"atoms": ()}, {"atoms": ("stuck(?x)",)}])
def test_out_of_range_parameters_are_refused_by_name(change):
    with pytest.raises(ParamsError) as exc:
        LiftedParams(**change)
    assert next(iter(change)) in str(exc.value)


def test_a_short_run_is_deterministic_and_grows_from_an_empty_population():
    params = LiftedParams(trials=150, sweep=50)
    a = train_lifted(params, np.random.default_rng(5))
    b = train_lifted(params, np.random.default_rng(5))
    assert a.classifiers == b.classifiers and a.steps == b.steps
    assert 0 < len(a.classifiers) <= a.covered + a.splits
    assert a.ground > 0 and a.reached <= a.trials
    assert all(set(c.condition) <= set("01#") for c in a.classifiers)
    assert all(c.condition[ATOMS.index("least-stuck(?x)")] == "#" for c in a.classifiers)  # not in READ_ATOMS
    every = train_lifted(LiftedParams(trials=150, sweep=50, atoms=ATOMS), np.random.default_rng(5))
    assert any(c.condition[ATOMS.index("least-stuck(?x)")] != "#" for c in every.classifiers)


def test_the_held_decision_is_practised_and_checkpoints_give_the_shorter_run():
    seen = {}
    params = LiftedParams(trials=200, sweep=50)
    run = train_lifted(params, np.random.default_rng(2), checkpoints={100, 150},
                       at_checkpoint=lambda k, classifiers: seen.setdefault(k, classifiers))
    assert set(seen) == {100, 150}
    assert seen[100] == train_lifted(LiftedParams(trials=100, sweep=50), np.random.default_rng(2)).classifiers
    assert seen[150] != run.classifiers
    assert any(c.condition[ATOMS.index("holding")] == "1" for c in run.classifiers)  # puts after its own picks


@pytest.fixture(scope="module")
def learned():
    """The default run from seed 0, what ``csql-sim train-lifted`` does (about 30 s)."""
    return train_lifted(LiftedParams(), np.random.default_rng(0))


@pytest.mark.slow
def test_default_run_reproduces_the_shipped_rules(learned):
    shipped = load_lifted_policy(SHIPPED)
    assert learned.classifiers == shipped.classifiers
    assert json.loads(SHIPPED.read_text())["meta"]["training"]["trials"] == learned.trials


@pytest.mark.slow
def test_learned_from_empty_population_plans_every_four_block_pair_optimally(learned):
    policy = learned.policy()
    assert len(learned.classifiers) < 50
    states = [unrank_state(r, 4) for r in range(state_count(4))]
    for start in states:
        for goal in states:
            run = rollout_relational(policy, start, goal)
            assert run.reached and run.length == optimal_length(start, goal), (start, goal)


@pytest.mark.slow
def test_learned_on_five_blocks_solves_every_pair_of_a_seeded_sample_at_ten(learned):
    policy = learned.policy()
    for start, goal in sample_pairs(10, 100, np.random.default_rng(10)):
        run = rollout_relational(policy, start, goal)
        assert run.reached, (start, goal, run.reason)


@pytest.fixture(scope="module")
def tall_26():
    """20 seeded tall-tower tasks of 26 blocks and their total exact optimum (about 20 s)."""
    rng = np.random.default_rng(26)
    pairs = [(tall_towers(26, rng), tall_towers(26, rng)) for _ in range(20)]
    return pairs, sum(optimal_length(start, goal) for start, goal in pairs)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(10))
def test_every_seed_at_the_defaults_solves_a_sample_at_ten_and_tall_towers_near_the_optimum(seed, tall_26):
    policy = train_lifted(LiftedParams(), np.random.default_rng(seed)).policy()
    for start, goal in sample_pairs(10, 200, np.random.default_rng(200)):
        run = rollout_relational(policy, start, goal)
        assert run.reached, (seed, start, goal, run.reason)
    # with least-stuck(?x) read as well, seeds 3, 5, 6, 8 and 9 needed 0.8-1.3% more than the optimum here
    pairs, optimum = tall_26
    runs = [rollout_relational(policy, start, goal) for start, goal in pairs]
    assert all(run.reached for run in runs)
    assert sum(run.length for run in runs) <= 1.005 * optimum, (seed, sum(run.length for run in runs), optimum)
