import numpy as np
import pytest

from csql_sim.core.state.message import format_state_message
from csql_sim.core.state.world import BlocksWorld
from csql_sim.envs.symbolic import BlocksWorldEnv, run_env_episode
from csql_sim.infra.errors import CsqlError
from csql_sim.learners.paper.trial import run_trial
from csql_sim.learners.training.tabular import make_learner


@pytest.mark.parametrize("n", [2, 3])
def test_mask_and_step_agree_with_the_world_model_everywhere(n):
    env = BlocksWorldEnv(n)
    world = BlocksWorld.of(n)
    count = len(world.states)
    for s in range(count):
        goal = (s + 1) % count
        for a in range(len(world.actions)):
            obs, info = env.reset(options={"start": s, "goal": goal})
            assert obs == format_state_message(world.states[s], goal)
            assert env.observation_space.contains(obs)
            assert np.flatnonzero(info["action_mask"]).tolist() == list(world.legal[s])
            obs, reward, terminated, truncated, info = env.step(a)
            want = world.next_state[s][a]
            assert info["illegal"] == (want < 0)
            expected = s if want < 0 else want
            assert obs == format_state_message(world.states[expected], goal)
            assert terminated == (expected == goal) and reward == float(terminated) and not truncated


def test_reset_draws_distinct_tasks_reproducibly_and_accepts_configurations():
    env = BlocksWorldEnv(3)
    draws = [env.reset(seed=7)[0] for _ in range(2)]
    assert draws[0] == draws[1]
    for seed in range(30):
        _, info = env.reset(seed=seed)
        assert info["state"] != info["goal"]
    _, info = env.reset(options={"start": "CBA", "goal": "BAC"})
    assert info["state"].notation() == "CBA" and info["goal"].notation() == "BAC"
    with pytest.raises(CsqlError):
        env.reset(options={"start": "CBA", "goal": "CBA"})
    with pytest.raises(CsqlError):
        env.step(99)


def test_truncation_after_max_steps():
    env = BlocksWorldEnv(3, max_steps=2)
    env.reset(options={"start": "CBA", "goal": "BAC"})
    assert env.step(0)[3] is False
    # A is held after the first unstack(A,B), so the second is illegal: state unchanged, truncated at 2 steps
    assert env.step(0)[3] is True


@pytest.mark.parametrize("method", ["cs-ql", "lt-ql", "cs-bb-bz"])
def test_learning_on_the_env_equals_learning_on_the_world_model(method):
    model, agent = make_learner(method, seed=2), make_learner(method, seed=2)
    env = BlocksWorldEnv(3)
    tasks = np.random.default_rng(0).integers(22, size=(150, 2))
    for k, (s, g) in enumerate(tasks):
        if s == g:
            continue
        temperature = model.params.temperature(k)
        result = run_trial(model, int(s), int(g), temperature)
        steps, reached = run_env_episode(env, agent, temperature, {"start": int(s), "goal": int(g)})
        assert (steps, reached) == (result.steps, result.reached)
    a, b = model.rulebase(), agent.rulebase()
    assert [(c.condition, c.action, c.q, c.strength) for c in a.classifiers if c.kind == "Q"] == [
        (c.condition, c.action, c.q, c.strength) for c in b.classifiers if c.kind == "Q"
    ]
