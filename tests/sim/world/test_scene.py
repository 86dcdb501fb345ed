import dataclasses

import pytest

from csql_sim.core.state.notation import parse_config
from csql_sim.sim.control.physical import PhysicalWorld, SimError
from csql_sim.sim.world.config import DEFAULT_CONFIG
from csql_sim.sim.world.scene import Scene


def test_scene_bodies_by_name_and_own_client():
    with Scene(3) as a, Scene(3) as b:
        assert set(a.bodies) == {"table", "panda", "A", "B", "C"}
        assert a.client != b.client
        assert a.body_count() == 5
        assert not a.replay_only and a.steps == 0
        a.step(3)
        assert a.steps == 3 and b.steps == 0


def test_config_is_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        DEFAULT_CONFIG.physics.cube_size = 0.1  # type: ignore[misc]


def test_no_constraint_attaches_a_block_while_holding():
    with PhysicalWorld(3) as world:
        world.build(parse_config("AB+C"))
        panda = world.scene.bodies["panda"]
        assert world.scene.constraint_bodies() == [(panda, panda)]  # only the finger gear of the robot itself
        assert world.panda.grips(world.scene.block_body(2))
        assert world.scene.block_pose(2).position[2] > 0.08


def test_build_rejects_other_block_count():
    with PhysicalWorld(3) as world, pytest.raises(SimError):
        world.build(parse_config("AB"))


def test_bad_perception_mode():
    with pytest.raises(SimError):
        PhysicalWorld(3, perception="sonar")


def _moved(world, i, before):
    return max(abs(a - b) for a, b in zip(world.scene.block_pose(i).position, before, strict=True))


def test_sleeping_cubes_still_move_by_force_and_by_contact():
    physics = dataclasses.replace(DEFAULT_CONFIG.physics, sleep_threshold=1e-3)
    with PhysicalWorld(3, config=dataclasses.replace(DEFAULT_CONFIG, physics=physics)) as world:
        world.build(parse_config("A,B,C"))
        scene = world.scene
        scene.step(720)  # three seconds at rest: Bullet lets them sleep after two
        start = [scene.block_pose(i).position for i in range(3)]
        (ax, ay, az), (_, by, _) = start[0], start[1]
        for _ in range(20):  # push A towards B along the row
            scene.apply_force(scene.block_body(0), (0.0, 4.0 if by > ay else -4.0, 0.0), (ax, ay, az))
            scene.step()
        scene.step(480)
        assert _moved(world, 0, start[0]) > 0.03  # the force moved the sleeping cube
        assert _moved(world, 1, start[1]) > 0.005  # A's contact moved B, asleep until A hit it
