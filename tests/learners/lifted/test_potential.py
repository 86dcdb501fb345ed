"""The tie-break over generated features: values by value iteration, the count fitted to them, its cost."""

import numpy as np

from csql_sim.core.features.denotation import Denotations
from csql_sim.core.features.formulation import load_formulation, primitive_arrays
from csql_sim.core.features.grammar import parse
from csql_sim.core.model.search import distance
from csql_sim.core.state.goal_relations import well_placed
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state_count import sample_hand_empty
from csql_sim.core.state.world import all_states
from csql_sim.learners.lifted.ground import GroundValues, PotentialCosts
from csql_sim.learners.lifted.potential import Potential, fit_potential, state_values


def test_value_iteration_gives_every_hand_empty_state_its_optimal_moves():
    states = list(all_states(4))
    goals = [parse_config("AB,CD"), parse_config("DCBA")]
    values = state_values(states, goals)
    hand_empty = [s for s in states if s.held is None]
    assert len(values) == len(hand_empty) * len(goals)
    for g in goals:
        for s in hand_empty:
            assert values[(s, g)] == distance(s, g) / 2, s.notation()


def test_the_fit_takes_the_count_most_correlated_with_the_values():
    """Of three concepts, the well-placed blocks' count predicts the moves left best (fewer left, more placed)."""
    rng = np.random.default_rng(0)
    form = load_formulation("move")
    goals = [sample_hand_empty(5, rng) for _ in range(6)]
    states = list(all_states(5))
    values = state_values(states, goals)
    pairs = [(s, g) for g in goals for s in states[::7] if s.held is None]
    prims, objects = primitive_arrays(form, [s for s, _ in pairs], [g for _, g in pairs])
    den = Denotations(prims, objects, form.constants)
    concepts = tuple(parse(t) for t in ("clear", "all(star(on),eq(on,on_g))", "on_g[1]"))
    fit = fit_potential(concepts, den, np.arange(len(pairs)), np.array([values[p] for p in pairs]))
    assert isinstance(fit, Potential) and fit.concept == "all(star(on),eq(on,on_g))"
    assert fit.slope < 0 and fit.correlation < -0.5 and fit.samples == len(pairs)
    placed = np.array([sum(well_placed(s, g)) for s, g in pairs])
    assert np.allclose(fit.of(placed + 1), fit.slope * (placed + 1) + fit.intercept)  # + 1: the table object
    assert fit_potential(concepts, den, np.arange(1), np.zeros(1)) is None  # nothing to fit on


def test_a_move_costs_its_reward_plus_early_times_the_estimate_after_it():
    costs = PotentialCosts(1, 0.1)
    ground = GroundValues(lambda s, t: ((), None), costs)
    state, target = parse_config("A,B,C"), parse_config("ABC")
    i = ground.of(state, target)
    assert ground.backup(i) == [1.0] * len(ground.successors(i))  # no estimate yet: the reward alone
    costs.estimate = lambda s, t: float(3 - sum(well_placed(s, t)))
    ground = GroundValues(lambda s, t: ((), None), costs)
    i = ground.of(state, target)
    q = ground.backup(i)
    after = [ground.keys[j][0] for j in ground.successors(i)]
    assert q == [1.0 + 0.1 * (3 - sum(well_placed(s, target))) for s in after]
