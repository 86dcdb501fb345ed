import itertools
import math

import numpy as np
import pytest

from csql_sim.core.state.notation import parse_action_name, parse_config
from csql_sim.sim.control.executor import run_physical_episode
from csql_sim.sim.control.physical import PhysicalWorld
from csql_sim.sim.control.recovery import Flatten, recovery_for
from csql_sim.sim.world.scene import quaternion_from_euler, rotation_matrix


def lean(world: PhysicalWorld, block: int, against: int, degrees: float) -> None:
    """Scene construction: stand ``block`` on one edge, leaning on ``against``'s +x face, and let it settle."""
    size = world.config.physics.cube_size
    base = world.scene.block_pose(against).position
    for sign in (1, -1):  # the edge on the table must be the one away from the other cube
        q = quaternion_from_euler((0.0, sign * math.radians(degrees), 0.0))
        signs = np.array(list(itertools.product((-1, 1), repeat=3)))
        corners = signs * size / 2 @ rotation_matrix(q).T
        if corners[np.argmin(corners[:, 2]), 0] > 0:
            break
    x = base[0] + size / 2 - corners[:, 0].min() + 5e-4
    world.scene.set_block_pose(block, (x, base[1], -corners[:, 2].min() + 5e-4), q)
    world.scene.step(240)


@pytest.mark.parametrize("perception", ["pose", "camera"])
def test_a_leaning_cube_is_seen_tilted_and_flattened(perception):
    with PhysicalWorld(2, seed=1, perception=perception) as world:
        world.build(parse_config("A,B"))
        lean(world, 1, 0, 30)
        seen = world.perceive()
        assert seen.state is None and seen.stray == 1, seen
        assert world.observe().blocks[1].tilt > math.radians(20)  # the camera sees the tilt in depth
        assert isinstance(recovery_for(seen), Flatten)
        name, status = world.recover(seen)
        assert name == "flatten(B)" and status.ok, status
        after = world.perceive()
        assert after.state == parse_config("A,B"), after.reason
        assert world.scene.constraint_bodies() == [(world.scene.bodies["panda"], world.scene.bodies["panda"])]


def test_no_recovery_for_a_state_or_a_fallen_cube():
    with PhysicalWorld(3) as world:
        world.build(parse_config("A,B,C"))
        assert recovery_for(world.perceive()) is None
        world.scene.set_block_pose(0, (1.2, 0, 0.02), (0, 0, 0, 1))
        world.scene.step(240)
        assert recovery_for(world.perceive()) is None


@pytest.mark.slow
def test_the_leaning_cube_episode_recovers():
    # the drop leaves A leaning on B; this episode used to end "block A is not resting flat anywhere"
    r = run_physical_episode(parse_config("A,B,C"), parse_config("CAB"), seed=9, perturb=True, perception="pose")
    assert r.success, r.reason
    assert [s.action for s in r.steps if s.recovery] == ["flatten(A)"]
    assert r.length == r.optimal_length + 3  # pickup and the dropped stack, the flatten, then the optimal plan


def test_a_cube_crowded_by_a_tower_is_dragged_clear_and_then_picked():
    with PhysicalWorld(5, seed=2) as world:
        world.build(parse_config("ABCD,E"))
        tower = np.asarray(world.scene.block_pose(0).position)
        world.scene.set_block_pose(4, (tower[0] + 0.02, tower[1] + 0.054, 0.0201), (0, 0, 0, 1))  # construction
        world.settle()
        assert world.perceive().state == parse_config("ABCD,E")
        blocked = [world.execute(parse_action_name("pickup(E)", 5), attempt=k) for k in range(2)]
        assert all(not s.ok and "collision" in s.reason for s in blocked), blocked
        before = np.asarray(world.scene.block_pose(4).position)
        name, status = world.recover(world.perceive(), blocked_pick=4)
        assert name == "drag(E)" and status.ok, status
        after = np.asarray(world.scene.block_pose(4).position)
        assert np.linalg.norm(after[:2] - tower[:2]) > np.linalg.norm(before[:2] - tower[:2]) + 0.03
        assert world.perceive().state == parse_config("ABCD,E")  # still flat on the table, the tower intact
        assert world.execute(parse_action_name("pickup(E)", 5)).ok
