"""One parser for every form a user types: configurations (A-Z), the paper's and relational messages."""

import pytest

from csql_sim.core.state.message import format_state_message, is_state_message
from csql_sim.core.state.notation import parse_action_name, parse_config, parse_state_arg
from csql_sim.core.state.relational_message import format_large_message, is_relational_message
from csql_sim.core.state.world import Action, ActionKind, BlocksWorld, WorldError


def test_configurations_of_up_to_26_letters():
    assert parse_config("CBA").n == 3 and parse_config("GFEDCBA").support[6] == -1
    assert parse_config("ZYXWVUTSRQPONMLKJIHGFEDCBA").n == 26
    with pytest.raises(WorldError, match="unknown block"):
        parse_config("AB7")


def test_state_arg_reads_the_paper_message_and_the_relational_one():
    state = parse_config("CBA")
    paper = format_state_message(state, BlocksWorld.of(3).state_index(parse_config("BAC")))
    assert parse_state_arg(paper) == state and not is_relational_message(paper)
    start, goal = parse_config("GFEDCBA"), parse_config("ABCDEFG")
    relational = format_large_message(start, goal)
    assert is_relational_message(relational) and parse_state_arg(relational) == start


def test_a_configuration_starting_with_s_is_not_a_message():
    assert not is_state_message("SRQPONMLKJIHGFEDCBA")
    assert parse_state_arg("SRQPONMLKJIHGFEDCBA").towers() == (tuple(range(18, -1, -1)),)


def test_action_names_past_z_name_the_blocks_the_configurations_name():
    """Issue 54: ``stack(AD,AC)`` of thirty cubes was refused (one letter a block): plans and reports past Z broke."""
    assert parse_action_name("stack(AD,AC)", 30) == Action(ActionKind.STACK, 29, 28)
    assert parse_action_name("unstack(aa, b)", 27) == Action(ActionKind.UNSTACK, 26, 1)
    assert parse_action_name("pickup(Z)", 26) == Action(ActionKind.PICKUP, 25)
    for text, n in (("pickup(AE)", 30), ("pickup(AA)", 26), ("pickup(Z)", 25)):
        with pytest.raises(WorldError, match="unknown block"):
            parse_action_name(text, n)
