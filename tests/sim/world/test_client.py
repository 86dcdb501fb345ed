import ast
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

import csql_sim
from csql_sim.sim.world.client import PhysicsClient, quaternion_from_euler, rotation_matrix
from csql_sim.sim.world.config import DEFAULT_CONFIG


def test_importing_pybullet_prints_no_banner():
    # pybullet's C banner ("pybullet build time: ...") reaches neither stdout nor stderr
    out = subprocess.run([sys.executable, "-c", "import csql_sim.sim.world.client; print('ok')"],
                         capture_output=True, text=True, check=True)
    assert (out.stdout, out.stderr) == ("ok\n", "")


def _imports(path: Path) -> set[str]:
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module.split(".")[0])
        elif isinstance(node, ast.Call) and getattr(node.func, "id", "") == "_import_quietly":
            names.add(node.args[0].value)
    return names


def test_only_the_client_module_imports_pybullet():
    package = Path(csql_sim.__file__).parent
    importers = sorted(str(p.relative_to(package)) for p in package.rglob("*.py")
                       if {"pybullet", "pybullet_data"} & _imports(p))
    assert importers == ["sim/world/client.py"]


def test_rotation_matrix_of_a_yaw_and_a_flip():
    yaw = 0.3
    np.testing.assert_allclose(rotation_matrix(quaternion_from_euler((0.0, 0.0, yaw))),
                               [[math.cos(yaw), -math.sin(yaw), 0], [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]],
                               atol=1e-12)
    np.testing.assert_allclose(rotation_matrix(quaternion_from_euler((math.pi, 0.0, 0.0))),
                               np.diag([1.0, -1.0, -1.0]), atol=1e-12)


def test_a_box_falls_onto_nothing_and_the_client_closes():
    with PhysicsClient(DEFAULT_CONFIG.physics) as client:
        box = client.add_box((0.02, 0.02, 0.02), 0.1, (1, 0, 0, 1), (0.0, 0.0, 1.0), linearDamping=0.0)
        assert client.body_count() == 1
        client.step(240)  # one simulated second of undamped free fall: z = 1 - g t^2 / 2
        assert client.steps == 240
        assert abs(client.body_pose(box).position[2] - (1.0 - 9.81 / 2)) < 0.05
        seen: list[int] = []
        client.add_step_hook(lambda c: seen.append(c.steps))
        client.step(2)
        assert seen == [241, 242]
    assert client.client == -1
    client.close()  # idempotent
