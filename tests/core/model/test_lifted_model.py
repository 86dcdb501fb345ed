import numpy as np
import pytest

from csql_sim.core.classifiers.lifted_rule import BLOCKS_WORLD, LiftedRuleError, parse_lifted_rules
from csql_sim.core.model.lifted_model import LiftedWorldModel
from csql_sim.core.state import notation as large_state_notation
from csql_sim.core.state import world as large_state
from csql_sim.core.state.state_count import sample_state
from csql_sim.core.state.world import all_states, is_legal, legal_actions, successor


@pytest.mark.parametrize("n", [3, 4])
def test_lifted_model_is_the_true_world_on_every_state(n):
    model = LiftedWorldModel(BLOCKS_WORLD)
    for state in all_states(n):
        rel = state
        assert model.legal_actions(rel) == legal_actions(state)
        for action in legal_actions(state):
            assert model.successor(rel, action) == successor(state, action)


@pytest.mark.parametrize("n", [8, 26])
def test_lifted_model_agrees_with_the_relational_operators_past_six_blocks(n):
    model, rng = LiftedWorldModel(BLOCKS_WORLD), np.random.default_rng(n)
    for _ in range(20):
        state = sample_state(n, rng)
        assert model.legal_actions(state) == large_state.legal_actions(state)
        for action in large_state.legal_actions(state):
            assert model.successor(state, action) == large_state.successor(state, action)


def test_a_weaker_precondition_is_what_the_model_follows():
    rules = parse_lifted_rules(["R S[held=?x] A[stack(?x,?y)]",
                                "R S[act=stack(?x,?y)] S[clear(?x)=1 clear(?y)=0 on(?x)=?y held=0]"])
    model = LiftedWorldModel(rules)
    state = large_state_notation.parse_config("BC+A")  # C on B, A held: only stack(A,C) is truly legal
    stacks = model.legal_actions(state)
    assert [large_state.action_name(a) for a in stacks] == ["stack(A,B)", "stack(A,C)"]
    assert [is_legal(state, a) for a in stacks] == [False, True]


def test_two_rules_for_one_operator_are_refused():
    with pytest.raises(LiftedRuleError):
        LiftedWorldModel([BLOCKS_WORLD[0], BLOCKS_WORLD[0]])
