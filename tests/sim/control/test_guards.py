import pytest

from csql_sim.core.state.notation import parse_action_name, parse_config
from csql_sim.sim.control.physical import PhysicalWorld


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
        assert not status.ok and status.refused and reason in status.reason
        assert world.scene.steps == steps  # no motion at all
        assert world.perceive().state == before


def test_a_legal_action_passes_its_guard():
    with PhysicalWorld(3, seed=0) as world:
        world.build(parse_config("AB,C"))
        status = world.execute(parse_action_name("unstack(B,A)", 3), guarded=True)
        assert status.ok and not status.refused
        assert world.perceive().state == parse_config("A,C+B")


def test_a_put_whose_cube_slid_off_is_a_failure():
    from csql_sim.sim.control.guards import missed_outcome
    from csql_sim.sim.perception.poses import TOLERANCES, BlockObs, Observation

    size = 0.04
    a = BlockObs((0.5, 0.0, size / 2), 0.0, 0.0)
    on_a = BlockObs((0.5, 0.0, 1.5 * size), 0.0, 0.0)
    beside = BlockObs((0.5, 0.1, size / 2), 0.0, 0.0)
    c = BlockObs((0.5, -0.2, size / 2), 0.0, 0.0)
    stack_b_a = parse_action_name("stack(B,A)", 3)
    slid = Observation((a, beside, c), (0.5, 0.0, 0.3), 0.08, size)
    assert missed_outcome(stack_b_a, slid, TOLERANCES) == "B did not come to rest on A"
    landed = Observation((a, on_a, c), (0.5, 0.0, 0.3), 0.08, size)
    assert missed_outcome(stack_b_a, landed, TOLERANCES) == ""
    assert missed_outcome(parse_action_name("putdown(B)", 3), slid, TOLERANCES) == ""
