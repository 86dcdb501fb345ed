import numpy as np
import pytest

from csql_sim.core.state.message import MessageError, layout
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.relational_message import (
    HELD_CHAR,
    TABLE_CHAR,
    format_large_action,
    format_large_message,
    message_length,
    parse_large_action,
    parse_large_message,
)
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.core.state.world import LETTERS, legal_actions


def test_table_and_held_symbols_are_not_letters():
    assert not TABLE_CHAR.isalpha() and not HELD_CHAR.isalpha()


def test_lengths_tell_every_n_apart_and_differ_from_the_papers_form():
    lengths = [message_length(n) for n in range(7, 27)]
    assert len(set(lengths)) == len(lengths)
    assert not set(lengths) & {layout(n).length for n in range(2, 7)}


@pytest.mark.parametrize("n", [7, 12, 26])
def test_messages_round_trip(n):
    rng = np.random.default_rng(n)
    for start, goal in sample_pairs(n, 30, rng):
        actions = legal_actions(start)
        action = actions[int(rng.integers(len(actions)))]
        for slot in (None, action):
            parsed = parse_large_message(format_large_message(start, goal, slot))
            assert (parsed.state, parsed.goal, parsed.action) == (start, goal, slot)
        assert parse_large_action(format_large_action(action, n), n) == action


def test_a_26_block_message_reads_as_documented():
    state = parse_config(LETTERS[:25] + "+" + "Z")  # one tower A..Y, Z held
    goal = parse_config(",".join(LETTERS))
    message = format_large_message(state, goal)
    assert message == "S000" + "0" * 24 + "10" + TABLE_CHAR + LETTERS[:24].lower() + "0z" + TABLE_CHAR * 26 + "0"
    assert len(message) == message_length(26) == 84


def test_malformed_messages_are_refused():
    start, goal = parse_config("ABCDEFG"), parse_config("A,B,C,D,E,F,G")
    good = format_large_message(start, goal)
    for pos, ch in ((0, "X"), (4, "1"), (12, "a"), (11, "t")):
        bad = good[:pos] + ch + good[pos + 1:]
        with pytest.raises(MessageError):
            parse_large_message(bad)
    with pytest.raises(MessageError):
        parse_large_message(good[:-1])
    with pytest.raises(MessageError):
        format_large_message(parse_config("AB"), parse_config("BA"))
