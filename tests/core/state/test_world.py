import pytest

from csql_sim.core.state.notation import parse_action_name, parse_config
from csql_sim.core.state.world import (
    HAND,
    TABLE,
    ActionKind,
    BlocksWorld,
    State,
    WorldError,
    all_actions,
    all_states,
    format_config,
    is_legal,
    legal_actions,
    successor,
)


@pytest.mark.parametrize(("n", "count"), [(2, 5), (3, 22), (4, 125), (5, 866)])
def test_state_counts(n, count):
    states = all_states(n)
    assert len(states) == count
    assert len(set(states)) == count


def test_n3_facts_from_the_paper():
    world = BlocksWorld.of(3)
    assert len(world.actions) == 18
    assert sum(s.held is None for s in world.states) == 13
    assert sum(len(acts) for acts in world.legal) == 42
    assert max(len(acts) for acts in world.legal) == 3


def test_state_order_is_stable_and_test_goal_is_code_C():
    states = all_states(3)
    assert states[0] == parse_config("A,B,C")
    assert states.index(parse_config("BAC")) == 12  # 'C' in base 36, as in Figure 6
    assert all(s.held is None for s in states[:13]) and all(s.held is not None for s in states[13:])


def test_action_order_matches_paper_codes():
    names = [a.name() for a in all_actions(3)]
    assert names[:9] == [
        "unstack(A,B)", "unstack(A,C)", "unstack(B,A)", "unstack(B,C)", "unstack(C,A)", "unstack(C,B)",
        "pickup(A)", "pickup(B)", "pickup(C)",
    ]
    assert names[9:] == [
        "putdown(A)", "putdown(B)", "putdown(C)",
        "stack(A,B)", "stack(A,C)", "stack(B,A)", "stack(B,C)", "stack(C,A)", "stack(C,B)",
    ]


@pytest.mark.parametrize("n", [2, 3, 4, 5])
def test_notation_round_trip_for_every_state(n):
    for s in all_states(n):
        assert parse_config(format_config(s)) == s
        assert parse_config(format_config(s).lower(), n) == s


@pytest.mark.parametrize("n", [2, 3, 4])
def test_successor_is_pure_and_moves_one_block(n):
    for s in all_states(n):
        for a in legal_actions(s):
            before = s.support
            t = successor(s, a)
            assert s.support == before
            changed = [i for i in range(n) if s.support[i] != t.support[i]]
            assert changed == [a.block]
            assert (t.held == a.block) == a.is_pick
        for a in all_actions(n):
            if not is_legal(s, a):
                with pytest.raises(WorldError):
                    successor(s, a)


def test_notation_meaning():
    s = parse_config("CBA")
    assert s.support == (1, 2, TABLE)  # A on B, B on C, C on the table
    h = parse_config("b,c+a")
    assert h.held == 0 and h.support == (HAND, TABLE, TABLE)
    assert parse_config(" a , b , c ") == parse_config("A,B,C")


@pytest.mark.parametrize(
    ("text", "n", "fragment"),
    [
        ("ABD", None, "unknown block D"),
        ("ABX", None, "unknown block X for a 3-block world"),
        ("AAB", None, "used twice"),
        ("AB", 3, "block C is missing"),
        ("A,,B", None, "empty tower"),
        ("A+B+C", None, "more than one"),
        ("A", None, "number of blocks"),
        ("ABCDEFA", None, "used twice"),
        ("", None, "empty"),
    ],
)
def test_bad_configurations(text, n, fragment):
    with pytest.raises(WorldError, match=fragment):
        parse_config(text, n)


def test_invalid_supports_rejected():
    with pytest.raises(WorldError):
        State((HAND, HAND, TABLE))
    with pytest.raises(WorldError):
        State((1, 0, TABLE))  # cycle
    with pytest.raises(WorldError):
        State((2, 2, TABLE))  # two blocks on C


def test_action_names_round_trip():
    for a in all_actions(4):
        assert parse_action_name(a.name(), 4) == a
    assert parse_action_name("Stack(a, b)", 3).kind is ActionKind.STACK
    with pytest.raises(WorldError):
        parse_action_name("fly(A)", 3)
    with pytest.raises(WorldError):
        parse_action_name("stack(A,A)", 3)
