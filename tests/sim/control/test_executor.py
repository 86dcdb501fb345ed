import numpy as np
import pytest

from csql_sim.core.model.search import distance
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import all_states
from csql_sim.sim.control.executor import Perturbation, PerturbationPlan, run_physical_episode


def test_test_task_reaches_goal_optimally(task):
    start, goal = task
    r = run_physical_episode(start, goal, seed=0)
    assert r.success, r.reason
    assert r.length == distance(start, goal) == 8
    assert r.optimal and not r.mismatches
    assert r.steps[-1].perceived == goal.notation()
    assert r.sim_seconds_per_action <= 1.0


def test_seeded_sample_of_pairs():
    states = all_states(3)
    pairs = [(s, g) for s in states for g in states if s != g]
    rng = np.random.default_rng(2024)
    for k in rng.choice(len(pairs), size=10, replace=False):
        start, goal = pairs[k]
        r = run_physical_episode(start, goal, seed=int(k))
        assert r.success, (start.notation(), goal.notation(), r.reason)
        assert r.length == distance(start, goal)


def test_same_seed_same_final_poses():
    start, goal = parse_config("A,BC"), parse_config("CAB")
    a = run_physical_episode(start, goal, seed=7, perturb=True)
    b = run_physical_episode(start, goal, seed=7, perturb=True)
    assert a.final_poses == b.final_poses
    assert a.success and b.success


def test_dropped_block_is_a_logged_mismatch_and_recovered():
    start, goal = parse_config("A,B,C"), parse_config("CA,B")
    forced = Perturbation(nudge_probability=0.0, drop_probability=1.0)
    r = run_physical_episode(start, goal, seed=0, perturb=True, perturbation=forced)
    assert any("gripper opened" in e for e in r.events)
    assert r.mismatches, "the drop must show up as a mismatch with the world model"
    assert r.success, r.reason
    assert r.length > distance(start, goal)


def test_nudge_is_physical_and_recovered():
    start, goal = parse_config("A,B,C"), parse_config("CBA")
    forced = Perturbation(nudge_probability=1.0, drop_probability=0.0)
    r = run_physical_episode(start, goal, seed=0, perturb=True, perturbation=forced)
    assert any(e.startswith("nudged") for e in r.events)
    assert r.success, r.reason


def test_camera_perception_episode(task):
    r = run_physical_episode(*task, seed=0, perception="camera")
    assert r.success, r.reason
    assert r.length == 8


class _SpyModel(WorldModel):
    """The built-in world model, counting predictions; ``wrong`` predicts "nothing changes"."""

    def __init__(self, wrong: bool = False) -> None:
        base = WorldModel.for_blocks(3)
        super().__init__(base.preconditions + base.add_deletes, 3)
        self.wrong = wrong
        self.calls = 0

    def predict_state(self, state, action, goal=0):
        self.calls += 1
        return state if self.wrong else super().predict_state(state, action, goal)


def test_predictions_come_from_the_world_model_passed_in(task):
    spy = _SpyModel()
    r = run_physical_episode(*task, seed=0, world_model=spy)
    assert r.success and spy.calls == r.length == 8
    assert [s.predicted for s in r.steps] == [s.perceived for s in r.steps]


def test_success_is_decided_by_perception_not_by_the_world_model(task):
    # a world model that predicts no change is wrong at every step: each step is a logged
    # mismatch, yet the episode succeeds because the perceived state is the goal
    r = run_physical_episode(*task, seed=0, world_model=_SpyModel(wrong=True))
    assert r.success and r.length == 8
    assert len(r.mismatches) == 8 and r.steps[-1].perceived == task[1].notation()


def test_perturbation_plan_is_drawn_from_the_episode_generator():
    always = Perturbation(nudge_probability=1.0, drop_probability=1.0)
    plans = [PerturbationPlan.draw(np.random.default_rng(3), 5, always) for _ in range(2)]
    assert plans[0] == plans[1] and 0 <= plans[0].nudge_at < 5 and 0 <= plans[0].drop_at < 5
    never = Perturbation(nudge_probability=0.0, drop_probability=0.0)
    assert PerturbationPlan.draw(np.random.default_rng(3), 5, never) == PerturbationPlan()


class _Stuck:
    name = "stuck"

    def act(self, state, goal):
        return None


def test_policy_without_action_fails_with_reason(task):
    r = run_physical_episode(*task, policy=_Stuck(), seed=0)
    assert not r.success and "policy gave no action" in r.reason


@pytest.mark.parametrize("held", ["AB+C", "B,C+A"])
def test_start_with_held_block(held):
    start = parse_config(held)
    goal = parse_config("A,B,C")
    r = run_physical_episode(start, goal, seed=0)
    assert r.success, r.reason


def test_learned_rule_base_runs_on_the_arm(task, tmp_path):
    from csql_sim.cli import main
    from csql_sim.core.policies.loader import load_policy

    out = tmp_path / "rules.yaml"
    assert main(["train", "--out", str(out), "--no-progress"]) == 0
    policy = load_policy(out, 3)
    assert policy.blocks == 3 and policy.name == "rules"
    r = run_physical_episode(*task, policy=policy, seed=0)
    assert r.success, r.reason
    assert r.length == 8


def test_rule_base_for_other_world_is_rejected(tmp_path):
    from csql_sim.cli import main
    from csql_sim.core.policies.loader import load_policy
    from csql_sim.infra.errors import CsqlError

    out = tmp_path / "rules2.yaml"
    assert main(["train", "--blocks", "2", "--trials", "50", "--out", str(out), "--no-progress"]) == 0
    with pytest.raises(CsqlError):
        load_policy(out, 3)


def test_four_blocks_reverse_tower():
    start, goal = parse_config("DCBA"), parse_config("ABCD")
    r = run_physical_episode(start, goal, seed=0)
    assert r.success, r.reason
    assert r.length == distance(start, goal)


def test_on_action_reports_progress_once_per_action():
    from csql_sim.core.state.notation import parse_config as config
    from csql_sim.sim.control.executor import run_physical_episode as execute

    calls: list[int] = []
    result = execute(config("A,B,C"), config("AB,C"), seed=0, on_action=calls.append)
    assert result.success and calls == list(range(1, result.length + 1)) == [1, 2]
