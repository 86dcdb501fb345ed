"""The physical scene: a table, a Franka Panda and n cubes in one physics client.

:class:`Scene` is a :class:`~csql_sim.sim.world.client.PhysicsClient` that builds the bodies
and names them in :attr:`Scene.bodies` (``"table"``, ``"panda"``, ``"A"``, ``"B"``, ..., ``"AA"``, ...).
Where the cubes start is :mod:`csql_sim.sim.world.layout`'s job; setting recorded poses for
rendering is :mod:`csql_sim.sim.video.replay`'s. This module does not import pybullet.
"""

from __future__ import annotations

from csql_sim.core.state.state import default_name
from csql_sim.sim.world.arm_state import check_arm_blocks
from csql_sim.sim.world.client import (
    PhysicsClient,
    Pose,
    Quat,
    Vec3,
    projection_matrix,
    quaternion_from_euler,
    rotation_matrix,
    view_matrix,
)
from csql_sim.sim.world.config import COLOURS, SimConfig, config_for, cube_colour
from csql_sim.sim.world.markers import PRINTED, apply_markers

TABLE_RGBA = (0.72, 0.6, 0.45, 1.0)
FINGER_LINKS = (9, 10)
PANDA_URDF = "franka_panda/panda.urdf"


class Scene(PhysicsClient):
    """A pybullet world with its own DIRECT client: table, Panda and ``n`` cubes.

    Args:
        n: number of cubes, 2..30 (:data:`~csql_sim.sim.world.config.MAX_ARM_BLOCKS`).
        config: geometry, physics and control settings (default: :func:`~csql_sim.sim.world.config.config_for` n).
        physics: False builds a replay-only scene for rendering (bodies, no stepping).
        renderer_plugin: (file, entry point) of a renderer plugin loaded before the bodies
            (:mod:`csql_sim.sim.video.renderer`); :attr:`opengl` tells whether it loaded.
    """

    def __init__(self, n: int, config: SimConfig | None = None, physics: bool = True,
                 renderer_plugin: tuple[str, str] | None = None) -> None:
        self.n = check_arm_blocks(n)
        config = config_for(n) if config is None else config
        self.config = config
        self.replay_only = not physics  # replay scenes are posed, never stepped
        super().__init__(config.physics, renderer_plugin)
        self.bodies: dict[str, int] = {}
        self._load_table()
        self._load_panda()
        for i in range(n):
            self._load_cube(default_name(i), cube_colour(i))
        if not self.opengl:  # the EGL plugin draws no mesh given by its vertices: painted boxes there (videos only)
            apply_markers(self, [self.bodies[default_name(i)] for i in range(n)], COLOURS)
        self.kinematics: PhysicsClient | None = None  # the arm's kinematic copy (ControlConfig.ik_model)
        self.tall_bases: frozenset[int] = frozenset()  # bottoms of the goal's tall towers (PhysicalWorld.expect)
        if physics and config.control.ik_model:
            self.kinematics = PhysicsClient(config.physics)
            self.kinematics.load_fixed_urdf(PANDA_URDF)

    def close(self) -> None:
        """Disconnect the scene's client and the kinematic copy's (idempotent)."""
        if self.kinematics is not None:
            self.kinematics.close()
        super().close()

    def _load_table(self) -> None:
        pc = self.config.physics
        self.bodies["table"] = self.add_box(pc.table_half_extents, 0.0, TABLE_RGBA, pc.table_centre,
                                            lateralFriction=pc.table_friction)

    def _load_panda(self) -> None:
        pc, cc = self.config.physics, self.config.control
        body = self.load_fixed_urdf(PANDA_URDF)
        self.bodies["panda"] = body
        for link in FINGER_LINKS:
            self.set_link_dynamics(body, link, lateralFriction=pc.finger_friction,
                                   spinningFriction=pc.finger_spinning_friction)
        # couple the two fingers so that they stay symmetric about the hand's axis
        self.add_gear(body, *FINGER_LINKS, ratio=-1, erp=0.1, max_force=50)
        for j, q in enumerate(cc.start_joints or cc.home_joints):
            self.reset_joint(body, j, q)
        for j in FINGER_LINKS:
            self.reset_joint(body, j, cc.finger_open)

    def _load_cube(self, name: str, rgba: tuple[float, float, float, float]) -> None:
        pc = self.config.physics
        marked = not self.opengl
        self.bodies[name] = self.add_box((pc.cube_size / 2,) * 3, pc.cube_mass, PRINTED if marked else rgba,
                                         (0.0, 0.0, -1.0), marked,
                                         lateralFriction=pc.cube_friction,
                                         spinningFriction=pc.cube_spinning_friction, rollingFriction=0.0)
        if pc.sleep_threshold > 0:
            self.allow_sleep(self.bodies[name], pc.sleep_threshold)

    @property
    def sim_time(self) -> float:
        """Simulated seconds since the scene was built."""
        return self.steps * self.config.physics.time_step

    def block_body(self, i: int) -> int:
        """The body id of block ``i``."""
        return self.bodies[default_name(i)]

    def pose(self, name: str) -> Pose:
        """The base pose of the named body."""
        return self.body_pose(self.bodies[name])

    def block_pose(self, i: int) -> Pose:
        """The pose of block ``i``."""
        return self.body_pose(self.block_body(i))

    def block_speed(self, i: int) -> tuple[float, float]:
        """Linear (m/s) and angular (rad/s) speed of block ``i``."""
        return self.body_speed(self.block_body(i))

    def set_block_pose(self, i: int, position: Vec3, orientation: Quat) -> None:
        """Teleport block ``i`` (scene construction, replay and tests; never during an episode)."""
        self.set_body_pose(self.block_body(i), position, orientation)


__all__ = [
    "Pose",
    "Quat",
    "Scene",
    "Vec3",
    "projection_matrix",
    "quaternion_from_euler",
    "rotation_matrix",
    "view_matrix",
]
