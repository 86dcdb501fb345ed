import pytest

from csql_sim.sim.physical import PhysicalWorld
from csql_sim.world import parse_action_name, parse_config


@pytest.mark.parametrize("start,action,reason", [
    ("AB,C", "pickup(A)", "B is on top of A"),
    ("AB,C", "unstack(A,C)", "nothing to grasp: A is not on C"),
    ("AB,C", "pickup(B)", "nothing to grasp: B is not on the table"),
    ("AB,C", "unstack(C,B)", "nothing to grasp: C is not on B"),
    ("A,B+C", "pickup(A)", "hand already full"),
    ("AB,C", "putdown(C)", "C is not in the gripper"),
    ("AB+C", "stack(C,A)", "B is on top of A"),
])
def test_illegal_actions_are_refused_before_moving(start, action, reason):
    with PhysicalWorld(3, seed=0) as world:
        world.build(parse_config(start))
        before = world.perceive().state
        steps = world.scene.steps
        status = world.execute(parse_action_name(action, 3), guarded=True)
        assert not status.ok and reason in status.reason
        assert world.scene.steps == steps  # no motion at all
        assert world.perceive().state == before


def test_a_legal_action_passes_its_guard():
    with PhysicalWorld(3, seed=0) as world:
        world.build(parse_config("AB,C"))
        status = world.execute(parse_action_name("unstack(B,A)", 3), guarded=True)
        assert status.ok
        assert world.perceive().state == parse_config("A,C+B")
