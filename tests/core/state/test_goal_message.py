"""The goal form of the message: layout, detectors, round trip, malformed messages refused."""

import numpy as np
import pytest

from csql_sim.core.state.goal_message import (
    GoalForm,
    detector_values,
    form_of,
    format_goal_message,
    parse_goal_message,
    pattern_problem,
)
from csql_sim.core.state.goal_message_index import pair_messages
from csql_sim.core.state.message import MessageError, format_state_message
from csql_sim.core.state.notation import parse_state_arg
from csql_sim.core.state.world import all_states


def test_test_task_message_spelled_out():
    # A on B on C, towards C on A on B: A stands on B in both (home), nothing is placed
    # (C is not on A), and only B's goal place (the table) is ready.
    m = format_goal_message(parse_state_arg("CBA", 3), parse_state_arg("BAC", 3))
    assert m == "S0100000bct0000" + "G" + "bta000" + "0" + "100000" + "000000" + "010000"
    assert len(m) == GoalForm(3).length == 41


@pytest.mark.parametrize("n,detectors", [(2, ()), (3, ("home", "placed", "ready")), (3, ("ready",)), (4, ("placed",))])
def test_round_trip_every_pair(n, detectors):
    form = GoalForm(n, detectors)
    states = all_states(n)
    step = 1 if n < 4 else 5  # n = 4: every fifth start, every goal
    for s in states[::step]:
        for g in states:
            parsed = parse_goal_message(format_goal_message(s, g, form, action_code=3), form)
            assert (parsed.state, parsed.goal, parsed.action_code) == (s, g, 3)


@pytest.mark.parametrize("n", [2, 3, 4])
def test_all_pairs_at_once_match_one_by_one(n):
    form = GoalForm(n)
    states = all_states(n)
    rows = pair_messages(form)
    rng = np.random.default_rng(n)
    for k in rng.choice(len(rows), 200):
        s, g = divmod(int(k), len(states))
        assert bytes(rows[k]).decode() == format_goal_message(states[s], states[g], form)


def test_placed_needs_everything_below_home():
    # goal: C on B on A; state: B on A, C on the table -> A and B placed, C not home
    values = detector_values(parse_state_arg("AB,C", 3), parse_state_arg("ABC", 3))
    assert values["placed"] == (True, True, False)
    assert values["ready"] == (True, False, True)  # C's goal place, B, is placed and clear


GOOD = format_goal_message(parse_state_arg("CBA", 3), parse_state_arg("BAC", 3))


@pytest.mark.parametrize("bad,where", [
    (GOOD[:-1], "characters"),
    ("T" + GOOD[1:], "position 0"),
    (GOOD[:15] + "X" + GOOD[16:], "position 15"),
    (GOOD[:16] + "a" + GOOD[17:], "position 16"),  # A on itself in the goal
    (GOOD[:23] + "0" + GOOD[24:], "position 23"),  # home[A] disagrees with the state and goal
    (GOOD[:16] + "cc" + GOOD[18:], "two blocks"),  # A and B both on C in the goal
])
def test_malformed_messages_are_refused_in_one_line(bad, where):
    with pytest.raises(MessageError) as info:
        parse_goal_message(bad, GoalForm(3))
    assert "\n" not in str(info.value) and where in str(info.value)


def test_patterns_and_forms():
    form = GoalForm(3)
    assert pattern_problem("S" + "#" * 14 + "G" + "#" * 25, form) is None
    assert "position 16" in pattern_problem("S" + "#" * 14 + "Gx" + "#" * 24, form)
    assert "characters" in pattern_problem("S###", form)
    assert form_of({}, 3) is None and form_of({"form": "goal", "detectors": ["ready"]}, 3) == GoalForm(3, ("ready",))
    with pytest.raises(MessageError):
        form_of({"form": "goal", "detectors": ["distance"]}, 3)
    with pytest.raises(MessageError):
        form_of({"form": "plan"}, 3)


@pytest.mark.parametrize("n,detectors", [(2, ()), (3, ("home", "placed", "ready")), (4, ("home",)), (5, ())])
def test_read_infers_blocks_and_detectors(n, detectors):
    states = all_states(n)
    m = format_goal_message(states[1], states[-1], GoalForm(n, detectors))
    from csql_sim.core.state.goal_message import is_goal_message, read_goal_message

    assert is_goal_message(m) and not is_goal_message("S0111000ttt0000C")
    assert not is_goal_message(format_state_message(all_states(5)[0], 600))  # goal code G.. at the tag's place
    parsed = read_goal_message(m)
    assert (parsed.state, parsed.goal) == (states[1], states[-1])
    with pytest.raises(MessageError, match="fit no"):
        read_goal_message(m + "0")
