import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from csql_sim.core.model.search import BfsPolicy
from csql_sim.envs.physical import PhysicalBlocksEnv


def test_same_interface_as_symbolic_env_and_reaches_goal():
    env = PhysicalBlocksEnv(render_mode="rgb_array", width=64, height=48)
    obs, info = env.reset(seed=0, options={"start": "A,B,C", "goal": "AB,C"})
    assert obs.startswith("S0111000ttt0000") and env.observation_space.contains(obs)
    assert info["action_mask"].dtype == np.int8
    illegal = int(np.flatnonzero(info["action_mask"] == 0)[0])
    obs2, reward, term, trunc, info2 = env.step(illegal)
    assert obs2 == obs and info2["illegal"] and reward == 0.0 and not term
    policy = BfsPolicy()
    for _ in range(4):
        action = policy.act(info["state"], info["goal"])
        obs, reward, term, trunc, info = env.step(env.world.action_index(action))
        if term or trunc:
            break
    assert term and reward == 1.0 and info["state"] == info["goal"]
    assert env.render().shape == (48, 64, 3)
    env.close()


def test_same_learning_agent_runs_in_symbolic_and_physical_env():
    from csql_sim.envs.symbolic import BlocksWorldEnv, run_env_episode
    from csql_sim.learners.paper.trial import run_trial
    from csql_sim.learners.training.tabular import make_learner

    agent = make_learner("cs-ql", seed=0)
    rng = np.random.default_rng(0)
    for k in range(2500):
        s, g = rng.integers(22, size=2)
        if s != g:
            run_trial(agent, int(s), int(g), agent.params.temperature(k))
    temperature = agent.params.temperature(2500)
    task = {"start": "CBA", "goal": "BAC"}
    assert run_env_episode(BlocksWorldEnv(3), agent, temperature, task) == (8, True)
    env = PhysicalBlocksEnv(3)
    assert run_env_episode(env, agent, temperature, task) == (8, True)
    env.close()


# One seeded episode with start and goal drawn by the env: BFS actions, then every
# observation and the final cube poses as JSON (floats written exactly by repr).
_EPISODE = """
import json, sys
from csql_sim.core.model.search import BfsPolicy
from csql_sim.envs.physical import PhysicalBlocksEnv
env = PhysicalBlocksEnv(3)
obs, info = env.reset(seed=int(sys.argv[1]))
seen, policy, done = [obs], BfsPolicy(), False
while not done:
    action = env.world.action_index(policy.act(info["state"], info["goal"]))
    obs, reward, term, trunc, info = env.step(action)
    seen.append(obs)
    done = term or trunc
poses = [[list(p.position), list(p.orientation)] for p in env.physical.final_poses()]
print(json.dumps({"seed": env.physics_seed, "observations": seen, "reached": term, "poses": poses}))
"""


def _episode_in_fresh_process(seed: int) -> dict:
    out = subprocess.run([sys.executable, "-c", _EPISODE, str(seed)], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def test_reset_seed_determines_the_episode_across_processes():
    a, b = _episode_in_fresh_process(11), _episode_in_fresh_process(11)
    assert a["reached"] and len(a["observations"]) > 2
    assert a == b  # same start, goal, physics seed, observations and bit-identical final poses
    other = _episode_in_fresh_process(12)
    assert (other["seed"], other["observations"][0]) != (a["seed"], a["observations"][0])


def test_reset_without_seed_continues_the_seeded_stream():
    env = PhysicalBlocksEnv(3)
    env.reset(seed=3)
    first = env.physics_seed
    env.reset()
    second = (env.physics_seed, env.state, env.goal)
    env.reset(seed=3)
    assert env.physics_seed == first
    env.reset()
    assert (env.physics_seed, env.state, env.goal) == second
    env.close()


@pytest.mark.slow
def test_eight_cubes_on_the_arm_through_the_environment():
    from csql_sim.core.policies.gn1 import Gn1Policy
    from csql_sim.core.state.notation import parse_config
    from csql_sim.core.state.relational_message import format_large_message
    from csql_sim.core.state.world import State, action_index

    env = PhysicalBlocksEnv(8, perception="camera", render_mode="rgb_array", width=64, height=48)
    obs, info = env.reset(seed=3, options={"start": "A,B,C,D,E,F,G,H", "goal": "HGFEDCBA"})
    assert isinstance(info["state"], State) and obs == format_large_message(info["state"], info["goal"])
    assert env.observation_space.contains(obs) and info["action_mask"].shape == (env.action_space.n,)
    policy, term, trunc = Gn1Policy(), False, False
    for _ in range(20):
        obs, reward, term, trunc, info = env.step(action_index(policy.act(info["state"], info["goal"]), 8))
        if term or trunc:
            break
    assert term and not trunc and reward == 1.0 and info["state"] == parse_config("HGFEDCBA")  # as perceived
    assert env.render().shape == (48, 64, 3)
    env.close()


# ------------------------------------------------------------------ past ten cubes: the ring (issue 54)
LIFTED = Path(__file__).resolve().parents[2] / "assets" / "rules" / "lifted.json"
RING_TASK = ("A,B,C,D,E,F,G,H,I,J,LK", "A,B,C,D,E,F,G,H,I,J,KL")  # twelve cubes: K on L becomes L on K


def _plan_file_actions(tmp_path):
    from csql_sim.core.files.ipc_plan import plan_index, read_plan
    from csql_sim.core.state.state import default_names

    plan = tmp_path / "ring.plan"
    plan.write_text("(unstack k l)\n(put-down k)\n(pick-up l)\n(stack l k)\n; cost = 4 (unit cost)\n")
    actions = iter([a for step in read_plan(plan, plan_index(default_names(12)), 12) for a in step.actions])
    return lambda state, goal: next(actions)


@pytest.mark.parametrize("agent", ["gn1", "lifted rules", "plan file"])
def test_twelve_cubes_on_the_arm_through_gymnasium_make(tmp_path, agent):
    import gymnasium

    import csql_sim.envs
    from csql_sim.core.policies.gn1 import Gn1Policy
    from csql_sim.core.policies.loader import load_policy
    from csql_sim.core.state.notation import parse_config
    from csql_sim.core.state.relational_message import format_large_message
    from csql_sim.core.state.world import action_index
    from csql_sim.envs.registration import PANDA_BLOCKS_ID

    gymnasium.register_envs(csql_sim.envs)
    act = {"gn1": lambda: Gn1Policy().act, "lifted rules": lambda: load_policy(LIFTED, 12).act,
           "plan file": lambda: _plan_file_actions(tmp_path)}[agent]()
    env = gymnasium.make(PANDA_BLOCKS_ID, blocks=12, perception="pose")
    obs, info = env.reset(seed=1, options={"start": RING_TASK[0], "goal": RING_TASK[1]})
    assert env.unwrapped.physical.scene.n == 12 and obs == format_large_message(info["state"], info["goal"])
    for _ in range(8):
        obs, reward, term, trunc, info = env.step(action_index(act(info["state"], info["goal"]), 12))
        assert obs == format_large_message(info["state"], info["goal"])  # the perceived state's message
        if term or trunc:
            break
    assert term and not trunc and reward == 1.0 and env.unwrapped.steps == 4
    assert info["state"] == parse_config(RING_TASK[1])  # as perceived
    env.close()


def test_twenty_eight_cubes_through_the_numeric_observation():
    from csql_sim.core.policies.gn1 import Gn1Policy
    from csql_sim.core.state.notation import parse_config
    from csql_sim.core.state.state import default_names
    from csql_sim.core.state.world import action_index
    from csql_sim.envs.numeric import state_of_code

    names = default_names(28)
    start, goal = ", ".join(names[:26]) + ", AA AB", ", ".join(names[:26]) + ", AB AA"
    env = PhysicalBlocksEnv(28, perception="pose", observation="numeric")
    obs, info = env.reset(seed=2, options={"start": start, "goal": goal})
    policy, term, trunc = Gn1Policy(), False, False
    for _ in range(6):
        obs, reward, term, trunc, info = env.step(action_index(policy.act(info["state"], info["goal"]), 28))
        if term or trunc:
            break
    assert term and not trunc and reward == 1.0 and state_of_code(obs["on"]) == parse_config(goal, 28)
    env.close()
