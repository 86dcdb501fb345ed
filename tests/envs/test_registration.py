import subprocess
import sys

import gymnasium
import numpy as np
import pytest

from csql_sim.core.classifiers.r_classifier import PreconditionRule, r_classifiers
from csql_sim.core.files.rulebase import RuleBase, save
from csql_sim.core.model.search import bfs_plan
from csql_sim.core.state.message import format_state_message
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import BlocksWorld, successor
from csql_sim.envs.registration import BLOCKS_WORLD_ID, PANDA_BLOCKS_ID, register_envs
from csql_sim.infra.errors import CsqlError

register_envs()


def test_import_has_no_side_effects():
    """``import csql_sim`` registers nothing and loads none of its layers."""
    code = ("import sys, gymnasium, csql_sim; "
            f"assert {BLOCKS_WORLD_ID!r} not in gymnasium.registry, 'registered on import'; "
            "assert not [m for m in sys.modules if m.startswith('csql_sim.')], 'layers imported'")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr


def test_register_envs_registers_both_ids_without_pybullet():
    code = ("import sys, gymnasium; from csql_sim.envs.registration import register_envs; register_envs(); "
            "register_envs(); "  # idempotent
            f"gymnasium.make({BLOCKS_WORLD_ID!r}, blocks=4).reset(seed=0); "
            f"assert {PANDA_BLOCKS_ID!r} in gymnasium.registry; "
            "assert 'pybullet' not in sys.modules, 'pybullet imported'")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr


def _python(code):
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                          check=False)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_importing_the_envs_module_registers_both_ids_as_gymnasium_1x_expects():
    """``import csql_sim.envs; gym.register_envs(csql_sim.envs); gym.make(id)``, in a fresh interpreter."""
    _python("import sys, gymnasium as gym, csql_sim.envs; gym.register_envs(csql_sim.envs); "
            f"env = gym.make({BLOCKS_WORLD_ID!r}, blocks=4); env.reset(seed=0); "
            f"assert {PANDA_BLOCKS_ID!r} in gym.registry; "
            "assert 'pybullet' not in sys.modules, 'pybullet imported'")


def test_the_module_colon_id_form_imports_and_makes():
    out = _python("import sys, gymnasium as gym; "
                  f"env = gym.make('csql_sim.envs:{BLOCKS_WORLD_ID}', blocks=3); obs, _ = env.reset(seed=1); "
                  "print(obs); assert 'pybullet' not in sys.modules")
    assert out.startswith("S") and len(out.strip()) == 16  # the paper's 3-block state message


@pytest.mark.parametrize("env_id, blocks", [(BLOCKS_WORLD_ID, 3), (PANDA_BLOCKS_ID, 3), (BLOCKS_WORLD_ID, 8),
                                            (PANDA_BLOCKS_ID, 8)])
def test_check_env_passes_without_a_warning(env_id, blocks):
    """Gymnasium's own checker on both environments, with every warning raised while it runs an error."""
    code = ("import warnings, gymnasium as gym, csql_sim.envs; from gymnasium.utils.env_checker import check_env\n"
            "with warnings.catch_warnings():\n"
            "    warnings.simplefilter('error')\n"
            f"    env = gym.make({env_id!r}, blocks={blocks}); check_env(env.unwrapped); env.close()\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr


def test_gymnasium_plugin_entry_point_is_installed_and_registers():
    """The ``gymnasium.envs`` entry point (loaded by Gymnasium 0.26-0.29) names register_envs."""
    from importlib.metadata import entry_points

    ours = [ep for ep in entry_points(group="gymnasium.envs") if ep.value.startswith("csql_sim.")]
    assert len(ours) == 1 and ours[0].load() is register_envs


def test_blocks_world_make_plays_an_optimal_plan_to_the_goal():
    env = gymnasium.make(BLOCKS_WORLD_ID, blocks=4, render_mode="ansi", max_steps=50)
    world = BlocksWorld.of(4)
    assert env.action_space.n == len(world.actions)
    start, goal = parse_config("DCBA"), parse_config("ABCD")
    obs, info = env.reset(seed=3, options={"start": start, "goal": goal})
    assert env.observation_space.contains(obs) and obs == format_state_message(start, world.state_index(goal))
    plan = bfs_plan(start, goal)
    for k, action in enumerate(plan, 1):
        index = world.actions.index(action)
        assert info["action_mask"][index] == 1
        obs, reward, terminated, truncated, info = env.step(index)
        assert terminated == (k == len(plan)) and reward == float(terminated) and not truncated
    assert info["state"] == goal and env.render().startswith(goal.notation())


def test_blocks_world_seeding_contract():
    a, b = gymnasium.make(BLOCKS_WORLD_ID, blocks=3), gymnasium.make(BLOCKS_WORLD_ID, blocks=3)
    tasks_a = [a.reset(seed=7)[0]] + [a.reset()[0] for _ in range(5)]
    tasks_b = [b.reset(seed=7)[0]] + [b.reset()[0] for _ in range(5)]
    assert tasks_a == tasks_b and len(set(tasks_a)) > 1


def test_rules_kwarg_sets_the_dynamics(tmp_path):
    """A rule file without the precondition rule of pickup(A) masks pickup(A) everywhere."""
    world = BlocksWorld.of(3)
    pickup_a = world.actions.index(next(a for a in world.actions if a.name() == "pickup(A)"))
    rules = list(r_classifiers(3))
    dropped = [r for r in rules if isinstance(r, PreconditionRule) and r.action[1] == f"{pickup_a + 1:X}"]
    assert len(dropped) == 1
    path = save(tmp_path / "r.yaml", RuleBase(3, [r for r in rules if r not in dropped]))
    env = gymnasium.make(BLOCKS_WORLD_ID, blocks=3, rules=str(path))
    full = gymnasium.make(BLOCKS_WORLD_ID, blocks=3)
    for s in range(len(world.states)):
        goal = (s + 1) % len(world.states)
        _, info = env.reset(options={"start": s, "goal": goal})
        _, info_full = full.reset(options={"start": s, "goal": goal})
        want = info_full["action_mask"].copy()
        want[pickup_a] = 0
        assert np.array_equal(info["action_mask"], want)
    with pytest.raises(CsqlError, match="rules for 3 blocks"):
        gymnasium.make(BLOCKS_WORLD_ID, blocks=4, rules=str(path))


def test_panda_blocks_make_runs_a_primitive_and_renders():
    env = gymnasium.make(PANDA_BLOCKS_ID, blocks=3, perception="pose", render_mode="rgb_array", width=64, height=48)
    try:
        world = BlocksWorld.of(3)
        start, goal = parse_config("CBA"), parse_config("BAC")
        obs, info = env.reset(seed=0, options={"start": start, "goal": goal})
        assert obs == format_state_message(start, world.state_index(goal))
        first = bfs_plan(start, goal)[0]
        obs, reward, terminated, truncated, info = env.step(world.actions.index(first))
        assert obs == format_state_message(successor(start, first), world.state_index(goal))
        assert (reward, terminated, truncated, info["failure"]) == (0.0, False, False, "")
        frame = env.render()
        assert frame.shape == (48, 64, 3) and frame.std() > 5
    finally:
        env.close()
