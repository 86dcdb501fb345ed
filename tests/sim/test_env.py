import numpy as np

from csql_sim.planner import BfsPolicy
from csql_sim.sim.env import PhysicalBlocksEnv


def test_same_interface_as_symbolic_env_and_reaches_goal():
    env = PhysicalBlocksEnv(render_mode="rgb_array", width=64, height=48)
    obs, info = env.reset(seed=0, options={"start": "A,B,C", "goal": "AB,C"})
    assert obs.startswith("S0111000ttt0000") and env.observation_space.contains(obs)
    assert info["action_mask"].dtype == np.int8
    illegal = int(np.flatnonzero(info["action_mask"] == 0)[0])
    obs2, reward, term, trunc, info2 = env.step(illegal)
    assert obs2 == obs and info2["illegal"] and reward == 0.0
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
    from csql_sim.env import BlocksWorldEnv, run_episode
    from csql_sim.learners import make_learner

    agent = make_learner("cs-ql", seed=0)
    rng = np.random.default_rng(0)
    for k in range(2500):
        s, g = rng.integers(22, size=2)
        if s != g:
            agent.run_trial(int(s), int(g), agent.params.temperature(k))
    temperature = agent.params.temperature(2500)
    task = {"start": "CBA", "goal": "BAC"}
    assert run_episode(BlocksWorldEnv(3), agent, temperature, task) == (8, True)
    env = PhysicalBlocksEnv(3)
    assert run_episode(env, agent, temperature, task) == (8, True)
    env.close()
