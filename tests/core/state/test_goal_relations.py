import pytest

from csql_sim.core.state.goal_relations import deadlocked, goal_place_ready, precedences, well_placed
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import WorldError


def test_well_placed_needs_everything_below_well_placed():
    state, goal = parse_config("ABC,D"), parse_config("DBC,A")  # B, C stand right on a wrong base
    assert well_placed(state, goal) == (True, False, False, True)


def test_goal_place_ready_is_the_table_or_a_clear_well_placed_block():
    state, goal = parse_config("AB,C,D"), parse_config("ABC,D")
    placed = well_placed(state, goal)
    assert goal_place_ready(state, goal, placed, 2)  # C onto B: B is well placed and clear
    state = parse_config("ABD,C")
    assert not goal_place_ready(state, goal, well_placed(state, goal), 2)  # D covers B


def test_two_blocks_each_over_the_others_goal_place_are_a_deadlock():
    state, goal = parse_config("AB,CD"), parse_config("AD,CB")
    assert deadlocked(state, goal) == {1, 3}
    assert precedences(state, goal).misplaced == (1, 3)


def test_no_deadlock_when_an_order_exists():
    assert deadlocked(parse_config("AB,C"), parse_config("A,CB")) == frozenset()


def test_held_blocks_have_no_deadlock_graph():
    with pytest.raises(WorldError):
        precedences(parse_config("A+B"), parse_config("AB"))
