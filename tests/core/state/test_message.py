import pytest

from csql_sim.core.state.message import (
    MessageError,
    format_action_message,
    format_state_message,
    layout,
    parse_action_message,
    parse_state_message,
)
from csql_sim.core.state.notation import parse_config, parse_state_arg
from csql_sim.core.state.world import all_actions, all_states


def test_paper_worked_examples_to_the_letter():
    goal = all_states(3).index(parse_config("BAC"))
    start = parse_config("A,B,C")
    msg = format_state_message(start, goal)
    assert msg == "S0111000ttt0000C"
    assert format_state_message(start, goal, action_code=7) == "S7111000ttt0000C"
    held = parse_config("B,C+A")
    assert format_state_message(held, goal) == "S00110000tt000aC"


def test_figure6_messages():
    goal = all_states(3).index(parse_config("BAC"))
    assert format_state_message(parse_config("CBA"), goal) == "S0100000bct0000C"
    assert format_state_message(parse_config("CB+A"), goal) == "S00100000ct000aC"
    assert format_state_message(parse_config("BA+C"), goal) == "S0100000bt0000cC"


@pytest.mark.parametrize("n", [2, 3, 4, 5])
def test_every_state_round_trips(n):
    states = all_states(n)
    for i, s in enumerate(states):
        goal = (i * 7) % len(states)
        msg = format_state_message(s, goal)
        assert len(msg) == layout(n).length
        parsed = parse_state_message(msg)  # n inferred
        assert parsed.state == s and parsed.goal == goal and parsed.action_code == 0
        assert parse_state_message(msg, n).state == s


def test_layout_lengths():
    assert [layout(n).length for n in (2, 3, 4, 5, 6)] == [16, 16, 17, 18, 19]


@pytest.mark.parametrize("n", [3, 4, 5])
def test_action_messages_round_trip(n):
    for a in all_actions(n):
        msg = format_action_message(a, n)
        assert len(msg) == layout(n).length
        assert parse_action_message(msg, n) == a


def test_paper_action_messages():
    acts = all_actions(3)
    assert format_action_message(acts[0], 3) == "A10000001000ab00"
    assert format_action_message(acts[12], 3) == "AD0000000100ab00"


@pytest.mark.parametrize(
    ("msg", "pos", "char"),
    [
        ("X0111000ttt0000C", 0, "X"),
        ("S0111000txt0000C", 9, "x"),
        ("S0121000ttt0000C", 3, "2"),
        ("S0111000ttt0000Z", 15, "Z"),
        ("S0111000ttt000aC", 14, "a"),
        ("S0111100ttt0000C", 5, "1"),
        ("S0011000ttt0000C", 2, "0"),
    ],
)
def test_malformed_message_names_position_and_character(msg, pos, char):
    with pytest.raises(MessageError) as err:
        parse_state_message(msg, 3)
    text = str(err.value)
    assert f"position {pos}" in text and repr(char) in text
    assert "\n" not in text


def test_wrong_length_rejected():
    with pytest.raises(MessageError, match="characters"):
        parse_state_message("S0111000ttt000C", 3)


def test_malformed_action_message():
    with pytest.raises(MessageError, match="position 13"):
        parse_action_message("A10000001000ac00", 3)


def test_state_arg_accepts_both_forms():
    assert parse_state_arg("S0100000bct0000C") == parse_config("CBA")
    assert parse_state_arg("cba") == parse_config("CBA")


@pytest.mark.parametrize("text", ["S0111000ttt", "S0", "S0111000ttt0000"])
def test_a_truncated_message_says_how_long_it_must_be(text):
    """Not "unknown block 'S'": the message is named as too short, with the lengths it may have."""
    with pytest.raises(MessageError) as refused:
        parse_state_arg(text)
    said = str(refused.value)
    assert f"{text!r} is too short: {len(text)} characters" in said
    assert all(f"{layout(n).length} (" in said for n in range(2, 7))


def test_a_non_ascii_letter_that_uppercases_to_a_digit_is_refused():
    """'ı'.upper() == 'I' (code 18); the message alphabet is ASCII only."""
    with pytest.raises(MessageError):
        parse_state_message("S0111000ttt0000\u0131", 3)
