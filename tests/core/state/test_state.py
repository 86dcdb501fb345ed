import pytest

from csql_sim.core.state import world
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import (
    HAND,
    TABLE,
    State,
    WorldError,
    action_at,
    action_count,
    action_index,
    action_name,
    legal_actions,
    successor,
)


def test_notation_round_trips_at_26_blocks():
    text = "ZYX,ABCDEFGHIJKLMNOPQRSTU,V+W"
    state = parse_config(text)
    assert state.n == 26 and state.held == 22 and state.support[0] == TABLE and state.support[1] == 0
    assert state.notation() == "ABCDEFGHIJKLMNOPQRSTU,V,ZYX+W"
    assert parse_config(state.notation()) == state


@pytest.mark.parametrize("n", [3, 4, 5])
def test_same_states_operators_and_names_as_the_enumerated_world(n):
    for state in world.all_states(n):
        rel = state
        assert parse_config(state.notation()) == rel == parse_config(rel.notation())
        assert legal_actions(rel) == world.legal_actions(state)
        for action in legal_actions(rel):
            assert successor(rel, action) == world.successor(state, action)
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
        parse_config(text)


@pytest.mark.parametrize("support", [(1, 0), (HAND, HAND), (0, 0, TABLE), (1, HAND), (), (TABLE, 2, 1), (0, 3, 1, 2)])
def test_impossible_states_are_refused(support):
    with pytest.raises(WorldError):
        State(support)


def test_illegal_action_is_refused():
    state = parse_config("AB")
    with pytest.raises(WorldError):
        successor(state, world.Action(world.ActionKind.PICKUP, 0))
