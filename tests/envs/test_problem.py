"""The ``problem`` reset option: a PDDL problem's start, (partial) goal and object names (issue 54)."""

from pathlib import Path

import numpy as np
import pytest

from csql_sim.core.files.ipc_plan import read_plan
from csql_sim.core.files.pddl_import import read_problem
from csql_sim.core.state.world import TABLE, Action, ActionKind, action_index
from csql_sim.envs.symbolic import BlocksWorldEnv
from csql_sim.infra.errors import CsqlError

LARGE = Path(__file__).resolve().parents[1] / "data" / "large"
TWELVE, TWELVE_PLAN = LARGE / "blocks12-names.pddl", LARGE / "blocks12-names.plan"
# four blocks, own names; the goal places two of them and leaves the others free
FOUR = """(define (problem four) (:domain blocks) (:objects Zeta alpha b10 b2)
  (:init (handempty) (ontable b2) (on alpha b2) (on Zeta alpha) (clear Zeta) (ontable b10) (clear b10))
  (:goal (and (on b2 Zeta) (ontable b10))))"""


def _four(tmp_path):
    path = tmp_path / "four.pddl"
    path.write_text(FOUR)
    return path


def _goal_of_four(state):
    """``(on b2 Zeta) (ontable b10)``, written out: the names sort as alpha, b2, b10, Zeta (A, B, C, D)."""
    return state.support[1] == 3 and state.support[2] == TABLE


def test_a_partial_goal_terminates_exactly_when_its_atoms_hold(tmp_path):
    env = BlocksWorldEnv(4, render_mode="ansi")
    rng = np.random.default_rng(0)
    satisfying = set()
    four = read_problem(_four(tmp_path))  # read once: a read problem is taken as well as its file
    for episode in range(40):
        obs, info = env.reset(options={"problem": _four(tmp_path) if episode == 0 else four})
        assert env.observation_space.contains(obs) and _goal_of_four(info["goal"]) and not _goal_of_four(info["state"])
        for _ in range(60):
            obs, reward, terminated, truncated, info = env.step(int(rng.choice(np.flatnonzero(info["action_mask"]))))
            state = info["state"]
            assert terminated == _goal_of_four(state) and reward == float(terminated) and not truncated
            if terminated:
                satisfying.add(state)
                break
    assert len(satisfying) > 1  # terminated in several goal states, not only the one the observation shows
    assert info["names"] == ("alpha", "b2", "b10", "Zeta")
    assert info["goal_atoms"] == ("(on b2 Zeta)", "(ontable b10)")


def test_twelve_named_blocks_reach_the_partial_goal_by_the_plan_file():
    problem = read_problem(TWELVE)
    actions = [a for step in read_plan(TWELVE_PLAN, problem.index, 12, problem.actions) for a in step.actions]
    env = BlocksWorldEnv(12, render_mode="ansi")
    obs, info = env.reset(options={"problem": str(TWELVE)})
    assert env.observation_space.contains(obs) and len(obs) == 3 * 12 + 5
    assert info["names"] == problem.names and "x-ray" in info["names"] and "Ruby" in info["names"]
    assert env.render().startswith("b2 Ruby jade, b10 x-ray")
    assert env.action_name(action_index(actions[0], 12)) == "unstack(jade,Ruby)"
    ends = [env.step(action_index(a, 12))[2] for a in actions]
    assert ends == [False] * 5 + [True] and problem.goal.satisfied(env.current)
    assert env.render().startswith("b2 Ruby, b10 x-ray jade, ivory, onyx")


def test_past_26_blocks_the_numeric_observation_takes_a_problem(tmp_path):
    names = " ".join(f"c{i}" for i in range(27))  # sorted as numbers: c0 is block 0, c26 block 26
    init = " ".join(f"(ontable c{i}) (clear c{i})" for i in range(27))
    path = tmp_path / "p27.pddl"
    path.write_text(f"(define (problem p) (:domain blocks) (:objects {names}) (:init (handempty) {init}) "
                    f"(:goal (on c26 c0)))")
    env = BlocksWorldEnv(27, observation="numeric")
    obs, info = env.reset(options={"problem": path})
    assert env.observation_space.contains(obs) and obs["goal"][26] == 1  # c26 on block 1 (c0) in the code
    assert info["names"][26] == "c26" and info["goal_atoms"] == ("(on c26 c0)",)
    pick, stack = action_index(Action(ActionKind.PICKUP, 26), 27), action_index(Action(ActionKind.STACK, 26, 0), 27)
    assert env.action_name(pick) == "pickup(c26)" and env.action_name(stack) == "stack(c26,c0)"
    assert not env.step(pick)[2] and env.step(stack)[2]


@pytest.mark.parametrize(("n", "options", "words"), [
    (11, {"problem": TWELVE}, "the problem has 12 blocks, the environment 11"),
    (12, {"problem": TWELVE, "start": 0}, "without start"),
    (12, {"problem": TWELVE, "goal": "A,B,C,D,E,F,G,H,I,J,K,L"}, "without goal"),
    (12, {"problem": 12}, "must be a PDDL problem file's path"),
    (12, {"problem": LARGE / "missing.pddl"}, "missing.pddl"),
    (12, {"problem": "BROKEN"}, "broken.pddl"),
    (4, {"problem": "SOLVED"}, "already satisfies the goal"),
])
def test_a_bad_problem_is_refused_in_one_line(tmp_path, n, options, words):
    broken = tmp_path / "broken.pddl"
    broken.write_text("(define (problem p) (:domain blocks) (:objects a b) (:init (ontable a (ontable b))")
    solved = tmp_path / "solved.pddl"
    solved.write_text(FOUR.replace("(on b2 Zeta)", "(on Zeta alpha)"))
    options = {k: {"BROKEN": broken, "SOLVED": solved}.get(v, v) if isinstance(v, str) else v
               for k, v in options.items()}
    with pytest.raises(CsqlError) as refused:
        BlocksWorldEnv(n).reset(options=options)
    assert words in str(refused.value) and "\n" not in str(refused.value)


def test_without_a_problem_the_names_are_the_letters_and_the_goal_is_one_state():
    env = BlocksWorldEnv(3)
    _, info = env.reset(options={"start": "CBA", "goal": "BAC"})
    assert info["names"] == ("A", "B", "C")
    assert info["goal_atoms"] == ("(handempty)", "(on A B)", "(on C A)", "(ontable B)")


@pytest.mark.parametrize("driver", ["gn1", "plan"])
def test_the_arm_takes_twelve_named_cubes_to_the_partial_goal_and_reports_the_names(driver):
    from csql_sim.core.policies.gn1 import Gn1Policy
    from csql_sim.envs.physical import PhysicalBlocksEnv

    problem = read_problem(TWELVE)
    plan = iter(a for step in read_plan(TWELVE_PLAN, problem.index, 12, problem.actions) for a in step.actions)
    env = PhysicalBlocksEnv(12, perception="pose")
    obs, info = env.reset(seed=0, options={"problem": TWELVE})
    assert env.observation_space.contains(obs) and info["names"] == problem.names
    names, terminated = [], False
    while not terminated and len(names) < 12:
        action = Gn1Policy().act(info["state"], info["goal"]) if driver == "gn1" else next(plan)
        names.append(env.action_name(action_index(action, 12)))
        obs, reward, terminated, truncated, info = env.step(action_index(action, 12))
        assert terminated == problem.goal.satisfied(info["state"]) and not truncated, info["failure"]
    env.close()
    assert terminated and reward == 1.0 and len(names) == 6 and info["names"] == problem.names
    assert {"stack(jade,x-ray)", "stack(pearl,zircon)"} <= set(names)
