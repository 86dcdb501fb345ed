import dataclasses
import math
import subprocess
import sys

import numpy as np
import pytest

from csql_sim.sim.config import DEFAULT_CONFIG
from csql_sim.sim.physical import PhysicalWorld, SimError
from csql_sim.sim.scene import Scene, quaternion_from_euler, rotation_matrix
from csql_sim.world import parse_config


def test_scene_bodies_by_name_and_own_client():
    with Scene(3) as a, Scene(3) as b:
        assert set(a.bodies) == {"table", "panda", "A", "B", "C"}
        assert a.client != b.client
        assert a.body_count() == 5


def test_importing_pybullet_keeps_stdout_clean():
    # pybullet's C banner ("pybullet build time: ...") goes to stderr, not to stdout
    out = subprocess.run([sys.executable, "-c", "import csql_sim.sim.scene; print('ok')"],
                         capture_output=True, text=True, check=True)
    assert out.stdout == "ok\n"


def test_rotation_matrix_of_a_yaw_and_a_flip():
    yaw = 0.3
    np.testing.assert_allclose(rotation_matrix(quaternion_from_euler((0.0, 0.0, yaw))),
                               [[math.cos(yaw), -math.sin(yaw), 0], [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]],
                               atol=1e-12)
    np.testing.assert_allclose(rotation_matrix(quaternion_from_euler((math.pi, 0.0, 0.0))),
                               np.diag([1.0, -1.0, -1.0]), atol=1e-12)


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
