import dataclasses

import pybullet
import pytest

from csql_sim.sim.config import DEFAULT_CONFIG
from csql_sim.sim.physical import PhysicalWorld, SimError
from csql_sim.sim.scene import Scene
from csql_sim.world import parse_config


def test_scene_bodies_by_name_and_own_client():
    with Scene(3) as a, Scene(3) as b:
        assert set(a.bodies) == {"table", "panda", "A", "B", "C"}
        assert a.client != b.client
        assert pybullet.getNumBodies(physicsClientId=a.client) == 5


def test_config_is_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        DEFAULT_CONFIG.physics.cube_size = 0.1  # type: ignore[misc]


def test_no_constraint_attaches_a_block_while_holding():
    with PhysicalWorld(3) as world:
        world.build(parse_config("AB+C"))
        cid = world.scene.client
        panda = world.scene.bodies["panda"]
        for k in range(pybullet.getNumConstraints(physicsClientId=cid)):
            info = pybullet.getConstraintInfo(pybullet.getConstraintUniqueId(k, physicsClientId=cid),
                                              physicsClientId=cid)
            assert info[0] == panda and info[2] == panda  # only the finger gear of the robot itself
        assert world.panda.grips(world.scene.block_body(2))
        assert world.scene.block_pose(2).position[2] > 0.08


def test_build_rejects_other_block_count():
    with PhysicalWorld(3) as world, pytest.raises(SimError):
        world.build(parse_config("AB"))


def test_bad_perception_mode():
    with pytest.raises(SimError):
        PhysicalWorld(3, perception="sonar")
