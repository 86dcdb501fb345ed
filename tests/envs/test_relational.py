"""The environments past six blocks: relational states, large messages, tasks by state, notation or rank."""

import numpy as np
import pytest

from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.relational_message import format_large_message, message_length
from csql_sim.core.state.state_count import rank_state, state_count
from csql_sim.core.state.world import State, action_at, action_count, action_index, legal_actions, successor
from csql_sim.envs.relational import check_env_blocks, large_mask, large_option, large_task
from csql_sim.envs.symbolic import BlocksWorldEnv
from csql_sim.infra.errors import CsqlError


@pytest.mark.parametrize("n", [7, 8, 10])
def test_observations_masks_and_steps_are_the_relational_worlds(n):
    env = BlocksWorldEnv(n)
    assert env.action_space.n == action_count(n)
    rng = np.random.default_rng(n)
    obs, info = env.reset(seed=n)
    assert isinstance(info["state"], State) and info["state"] != info["goal"]
    for _ in range(40):
        state, goal = info["state"], info["goal"]
        assert obs == format_large_message(state, goal) and len(obs) == message_length(n) == 3 * n + 5
        assert env.observation_space.contains(obs)
        legal = {action_index(a, n) for a in legal_actions(state)}
        assert set(np.flatnonzero(info["action_mask"]).tolist()) == legal
        a = int(rng.integers(action_count(n)))
        obs, reward, terminated, truncated, info = env.step(a)
        want = successor(state, action_at(a, n)) if a in legal else state
        assert info["illegal"] == (a not in legal) and info["state"] == want
        assert terminated == (want == goal) and reward == float(terminated) and not truncated
        if terminated:
            break


def test_gn1_reaches_the_goal_through_the_environment():
    env = BlocksWorldEnv(9, max_steps=200)
    obs, info = env.reset(seed=5, options={"start": "A,B,C,D,E,F,G,H,I", "goal": "IHGFEDCBA"})
    policy, reward, steps = Gn1Policy(), 0.0, 0
    terminated = False
    while not terminated:
        action = policy.act(info["state"], info["goal"])
        obs, reward, terminated, truncated, info = env.step(action_index(action, 9))
        steps += 1
        assert not truncated
    assert reward == 1.0 and info["state"] == parse_config("IHGFEDCBA") and steps == 16


def test_reset_takes_a_state_a_configuration_or_a_rank_and_draws_reproducibly():
    env = BlocksWorldEnv(8)
    goal = parse_config("HGFEDCBA")
    for given in (goal, "HGFEDCBA", rank_state(goal)):
        _, info = env.reset(options={"goal": given, "start": "A,B,C,D,E,F,GH"})
        assert info["goal"] == goal and info["state"] == parse_config("A,B,C,D,E,F,GH")
    first = [env.reset(seed=11)[0] for _ in range(2)]
    assert first[0] == first[1]
    assert len({env.reset()[0] for _ in range(5)}) == 5  # a seeded stream goes on, distinct tasks


@pytest.mark.parametrize("options, needle", [
    ({"start": "A,B,C,D,E,F,G,H", "goal": "A,B,C,D,E,F,G,H"}, "start and goal are the same state"),
    ({"goal": "A,B,C,D,E,F,G"}, "goal: block H is missing"),
    ({"goal": state_count(8)}, f"goal rank {state_count(8)} out of range 0..{state_count(8) - 1}"),
    ({"start": parse_config("A,B,C,D,E,F,G")}, "start has 7 blocks, the environment 8"),
    ({"start": 2.5}, "start must be a State, a configuration or a rank"),
])
def test_bad_tasks_are_refused_in_one_line(options, needle):
    with pytest.raises(CsqlError, match=needle) as caught:
        BlocksWorldEnv(8).reset(options=options)
    assert "\n" not in str(caught.value)


def test_past_six_blocks_rules_and_eleven_blocks_are_refused():
    with pytest.raises(CsqlError, match="give no rules"):
        BlocksWorldEnv(7, rules="rules.yaml")
    with pytest.raises(CsqlError, match=r"blocks must be an integer in 2..30, got 31"):
        BlocksWorldEnv(31)
    assert check_env_blocks(np.int64(30)) == 30
    with pytest.raises(CsqlError, match="observation='numeric'"):
        BlocksWorldEnv(27)


def test_the_pieces():
    state = parse_config("AB,C,D,E,F,G+H")
    mask = large_mask(state)
    assert mask.dtype == np.int8 and mask.sum() == 1 + 6  # put H down, or stack it on one of six clear blocks
    assert large_option(rank_state(state), 8, "start") == state == large_option("AB,C,D,E,F,G+H", 8, "start")
    start, goal = large_task(np.random.default_rng(0), 7, None, None)
    assert start != goal and start.n == goal.n == 7
