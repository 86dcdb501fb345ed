"""The numeric observation, the default step limit and render modes as Gymnasium specifies them (issue 52)."""

import subprocess
import sys
import warnings

import gymnasium
import numpy as np
import pytest

from csql_sim.core.model.search import bfs_plan
from csql_sim.core.state.notation import parse_action_name, parse_config
from csql_sim.core.state.world import BlocksWorld, action_index
from csql_sim.envs.numeric import numeric_space, state_of_code, support_code
from csql_sim.envs.physical import PhysicalBlocksEnv
from csql_sim.envs.registration import (
    BLOCKS_WORLD_ID,
    MAX_EPISODE_STEPS,
    PANDA_BLOCKS_ID,
    make_blocks_world,
    make_panda_blocks,
    register_envs,
)
from csql_sim.envs.symbolic import BlocksWorldEnv
from csql_sim.infra.errors import CsqlError

register_envs()


def test_every_state_of_three_blocks_round_trips_through_its_code():
    for state in BlocksWorld.of(3).states:
        code = support_code(state)
        assert numeric_space(3)["on"].contains(code) and state_of_code(code) == state


@pytest.mark.parametrize("code", [[0, 0, 5], [2, 1, 0], [4, 4, 0], [1, 0, 1]])
def test_a_code_that_is_no_configuration_is_refused(code):
    with pytest.raises(CsqlError):
        state_of_code(np.array(code))


TASKS = {3: ("CBA", "BAC"), 8: ("A,B,C,D,E,F,GH", "A,B,C,D,E,F,G,H")}


@pytest.mark.parametrize("n", sorted(TASKS))
def test_the_numeric_observation_is_the_state_the_goal_and_the_hand_along_a_plan(n):
    env = gymnasium.make(BLOCKS_WORLD_ID, blocks=n, observation="numeric")
    start, goal = (parse_config(c, n) for c in TASKS[n])
    obs, info = env.reset(seed=5, options={"start": start, "goal": goal})
    plan = bfs_plan(start, goal) if n <= 6 else [parse_action_name(a, n) for a in ("unstack(H,G)", "putdown(H)")]
    seen = []
    for action in plan:
        assert env.observation_space.contains(obs)
        assert state_of_code(obs["on"]) == info["state"] and state_of_code(obs["goal"]) == goal
        held = info["state"].held
        assert obs["hand"] == (0 if held is None else held + 1)
        seen.append(int(obs["hand"]))
        obs, reward, terminated, truncated, info = env.step(action_index(action, n))
    assert terminated and reward == 1.0 and state_of_code(obs["on"]) == goal and obs["hand"] == 0
    assert max(seen) > 0  # the plan held a block on the way


def test_the_numeric_spaces_are_those_stable_baselines3_accepts():
    """A Dict (not nested) of Box, Discrete and MultiDiscrete spaces of integers."""
    for n in (2, 4, 10):
        space = BlocksWorldEnv(n, observation="numeric").observation_space
        assert isinstance(space, gymnasium.spaces.Dict)
        for sub in space.spaces.values():
            assert type(sub) in (gymnasium.spaces.Box, gymnasium.spaces.Discrete, gymnasium.spaces.MultiDiscrete)
            assert np.issubdtype(sub.dtype, np.integer)
        assert space["on"].shape == (n,) and space["hand"].n == n + 1


@pytest.mark.parametrize("env_id, blocks", [(BLOCKS_WORLD_ID, 3), (BLOCKS_WORLD_ID, 8), (PANDA_BLOCKS_ID, 3)])
def test_check_env_passes_on_the_numeric_observation_without_a_warning(env_id, blocks):
    code = ("import warnings, gymnasium as gym, csql_sim.envs; from gymnasium.utils.env_checker import check_env\n"
            "with warnings.catch_warnings():\n"
            "    warnings.simplefilter('error')\n"
            f"    env = gym.make({env_id!r}, blocks={blocks}, observation='numeric'); check_env(env.unwrapped)\n"
            "    env.close()\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr


@pytest.mark.parametrize("observation", ["numbers", None, 1, "Numeric"])
def test_an_unknown_observation_is_refused(observation):
    with pytest.raises(CsqlError, match="observation"):
        BlocksWorldEnv(3, observation=observation)


def test_a_random_agent_is_truncated_at_the_registered_step_limit():
    env = gymnasium.make(BLOCKS_WORLD_ID, blocks=4)
    assert env.spec.max_episode_steps == MAX_EPISODE_STEPS
    _obs, info = env.reset(seed=0, options={"start": "DCBA", "goal": "ABCD"})
    illegal = int(np.flatnonzero(info["action_mask"] == 0)[0])  # the state never changes
    for step in range(1, MAX_EPISODE_STEPS + 1):
        *_, terminated, truncated, _info = env.step(illegal)
        assert not terminated and truncated == (step == MAX_EPISODE_STEPS)
    short = gymnasium.make(BLOCKS_WORLD_ID, blocks=4, max_episode_steps=3)
    short.reset(seed=0, options={"start": "DCBA", "goal": "ABCD"})
    assert [short.step(illegal)[3] for _ in range(3)] == [False, False, True]


def test_the_entry_points_carry_their_classes_metadata():
    assert make_blocks_world.metadata == BlocksWorldEnv.metadata
    assert make_panda_blocks.metadata == PhysicalBlocksEnv.metadata


@pytest.mark.parametrize("env_id, mode", [(BLOCKS_WORLD_ID, "rgb_array"), (BLOCKS_WORLD_ID, "human"),
                                          (PANDA_BLOCKS_ID, "ansi"), (BLOCKS_WORLD_ID, "video")])
def test_an_unsupported_render_mode_raises_gymnasiums_unsupported_mode(env_id, mode):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # gymnasium.make warns first, in its own words
        with pytest.raises(gymnasium.error.UnsupportedMode):
            gymnasium.make(env_id, render_mode=mode)
    with pytest.raises(gymnasium.error.UnsupportedMode):
        (BlocksWorldEnv if env_id == BLOCKS_WORLD_ID else PhysicalBlocksEnv)(render_mode=mode)


def test_rgb_array_list_on_the_arm_is_gymnasiums_render_collection():
    env = gymnasium.make(PANDA_BLOCKS_ID, blocks=3, render_mode="rgb_array_list", width=32, height=24)
    try:
        assert env.unwrapped.render_mode == "rgb_array"
        env.reset(seed=0, options={"start": "CBA", "goal": "BAC"})
        frames = env.render()
        assert isinstance(frames, list) and frames[0].shape == (24, 32, 3)
    finally:
        env.close()


def test_the_ansi_render_shows_the_message_whatever_the_observation():
    numeric, message = (BlocksWorldEnv(3, render_mode="ansi", observation=o) for o in ("numeric", "message"))
    text, _ = message.reset(options={"start": "CBA", "goal": "BAC"})
    numeric.reset(options={"start": "CBA", "goal": "BAC"})
    assert numeric.render() == message.render() == f"CBA  {text}"
