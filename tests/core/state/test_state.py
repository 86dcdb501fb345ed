import numpy as np
import pytest

from csql_sim.core.state import world
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state_count import sample_state
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


def test_default_names_are_letters_then_two_letters():
    from csql_sim.core.state.state import default_name, default_names

    assert default_names(3) == ("A", "B", "C")
    assert [default_name(i) for i in (25, 26, 27, 51, 52, 701, 702)] == ["Z", "AA", "AB", "AZ", "BA", "ZZ", "AAA"]
    assert len(set(default_names(1000))) == 1000


def test_one_block_and_a_thousand_blocks_are_states():
    one = State((TABLE,))
    assert one.n == 1 and one.notation() == "A" and legal_actions(one) == (world.Action(world.ActionKind.PICKUP, 0),)
    tower = State((TABLE, *range(999)))  # one tower of 1,000 blocks, block 0 at the bottom
    assert tower.is_clear(999) and not tower.is_clear(0) and tower.towers()[0] == tuple(range(1000))
    top = legal_actions(tower)
    assert [a.name() for a in top] == ["unstack(ALL,ALK)"]  # block 999's default name is ALL
    after = successor(tower, top[0])
    assert after.held == 999 and action_at(action_index(top[0], 1000), 1000) == top[0]
    assert after.notation().endswith("ALJ ALK + ALL")  # past 26 blocks names are separated


def test_names_ride_along_but_do_not_make_the_state():
    plain = State((TABLE, 0))
    named = plain.named(("Red", "blue"))
    assert named == plain and hash(named) == hash(plain) and {plain: 1}[named] == 1
    assert named.notation() == "AB" and named.named_notation() == "Red blue"
    assert plain.block_names == ("A", "B") and named.name(1) == "blue"
    with pytest.raises(WorldError, match="2 names for 3 blocks"):
        State((TABLE, TABLE, TABLE), ("a", "b"))
    with pytest.raises(WorldError, match="^two blocks stand on block amber$"):  # messages in the blocks' names
        State((TABLE, 0, 0), ("amber", "pearl", "onyx"))
    with pytest.raises(WorldError, match="^block pearl stands on itself$"):
        State((TABLE, 1), ("amber", "pearl"))


def test_a_change_checked_where_it_is_made_agrees_with_the_full_check():
    """Random one- and two-block changes of random states: with_changes refuses exactly what State refuses."""
    rng = np.random.default_rng(7)
    refused = accepted = 0
    for _ in range(3000):
        n = int(rng.integers(2, 9))
        state = sample_state(n, rng)
        changed = tuple(sorted({int(i) for i in rng.integers(0, n, int(rng.integers(1, 3)))}))
        support = list(state.support)
        for i in changed:
            support[i] = int(rng.integers(-2, n))
        support = tuple(support)
        try:
            State(support)
            full = None
        except WorldError:
            full = "refused"
        try:
            got = state.with_changes(support, changed)
        except WorldError:
            assert full == "refused", (state.support, support)
            refused += 1
            continue
        assert full is None and got == State(support) and got.names == state.names
        accepted += 1
    assert refused > 500 and accepted > 500
