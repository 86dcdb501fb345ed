import pytest

from csql_sim.core.state import world
from csql_sim.core.state.large_state import (
    LargeState,
    action_at,
    action_count,
    action_index,
    action_name,
    legal_actions,
    parse_large,
    successor,
)
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import HAND, TABLE, WorldError


def test_notation_round_trips_at_26_blocks():
    text = "ZYX,ABCDEFGHIJKLMNOPQRSTU,V+W"
    state = parse_large(text)
    assert state.n == 26 and state.held == 22 and state.support[0] == TABLE and state.support[1] == 0
    assert state.notation() == "ABCDEFGHIJKLMNOPQRSTU,V,ZYX+W"
    assert parse_large(state.notation()) == state


@pytest.mark.parametrize("n", [3, 4, 5])
def test_same_states_operators_and_names_as_the_enumerated_world(n):
    for state in world.all_states(n):
        rel = LargeState.from_state(state)
        assert parse_large(state.notation()) == rel == LargeState.from_state(parse_config(rel.notation()))
        assert legal_actions(rel) == world.legal_actions(state)
        for action in legal_actions(rel):
            assert successor(rel, action).to_state() == world.successor(state, action)
            assert action_name(action) == action.name()


@pytest.mark.parametrize("n", [2, 5, 6])
def test_action_index_is_the_stable_action_order(n):
    actions = world.all_actions(n)
    assert action_count(n) == len(actions)
    assert [action_index(a, n) for a in actions] == list(range(len(actions)))
    assert [action_at(i, n) for i in range(len(actions))] == list(actions)


@pytest.mark.parametrize("text", ["AB,A", "A,B,7", "", "A+B+C", "AB,,C", "AC"])
def test_bad_notation_is_refused(text):
    with pytest.raises(WorldError):
        parse_large(text)


@pytest.mark.parametrize("support", [(1, 0), (HAND, HAND), (0, 0, TABLE), (1, HAND), (TABLE,)])
def test_impossible_states_are_refused(support):
    with pytest.raises(WorldError):
        LargeState(support)


def test_illegal_action_is_refused():
    state = parse_large("AB")
    with pytest.raises(WorldError):
        successor(state, world.Action(world.ActionKind.PICKUP, 0))


def test_states_of_any_size_are_built_from_supports():
    state = LargeState((TABLE, *range(499)))
    assert state.n == 500 and state.towers() == (tuple(range(500)),)
