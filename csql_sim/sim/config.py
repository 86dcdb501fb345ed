"""Named constants of the physical world: geometry, physics, control, tolerances."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class PhysicsConfig:
    """Simulation and material settings."""

    time_step: float = 1.0 / 240.0  # seconds per stepSimulation
    solver_iterations: int = 50  # pybullet numSolverIterations
    gravity: float = -9.81  # m/s^2 along z
    cube_size: float = 0.04  # edge length of a cube, m
    cube_mass: float = 0.1  # kg
    cube_friction: float = 1.0  # lateral friction of cubes
    cube_spinning_friction: float = 0.001  # keeps resting cubes from spinning
    finger_friction: float = 1.5  # lateral friction of the finger pads
    finger_spinning_friction: float = 0.1  # torsional friction: a gripped cube does not pivot
    table_friction: float = 0.8  # lateral friction of the table top
    table_half_extents: tuple[float, float, float] = (0.45, 0.55, 0.02)  # m
    table_centre: tuple[float, float, float] = (0.45, 0.0, -0.02)  # top surface at z=0


@dataclass(frozen=True)
class LayoutConfig:
    """Where towers of the start scene stand and where putdown may place a block."""

    tower_x: float = 0.5  # x of the start towers, m
    tower_spacing: float = 0.12  # y distance between start towers, m
    free_x: tuple[float, ...] = (0.42, 0.50, 0.58)  # candidate putdown x, m
    free_y: tuple[float, ...] = (-0.24, -0.18, -0.12, -0.06, 0.0, 0.06, 0.12, 0.18, 0.24)  # m
    free_clearance: float = 0.085  # min xy distance of a putdown spot from any block, m
    jitter_xy: float = 0.006  # --perturb: max start offset of a block, m
    jitter_yaw: float = 0.12  # --perturb: max start yaw of a block, rad


@dataclass(frozen=True)
class ControlConfig:
    """Arm and gripper control; approach offsets are in ApproachOffsets (primitives)."""

    arm_forces: tuple[float, ...] = (87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0)  # N m
    arm_max_velocity: float = 2.6  # rad/s cap per joint
    arm_position_gain: float = 0.25  # pybullet positionGain
    finger_force: float = 40.0  # N per finger when closing
    finger_max_velocity: float = 0.4  # m/s
    finger_open: float = 0.04  # finger joint position when open, m
    ik_iterations: int = 40  # calculateInverseKinematics iterations
    ik_threshold: float = 1e-5  # IK residual, m
    reach_tolerance: float = 0.002  # end-effector distance counted as arrived, m
    arrive_speed: float = 0.05  # grasp point slower than this (m/s) counts as arrived
    check_every: int = 4  # steps between guard / arrival checks
    move_speed: float = 0.9  # mean grasp-point speed of free moves, m/s
    descend_speed: float = 0.45  # mean grasp-point speed of descents and lifts, m/s
    waypoint_spacing: float = 0.06  # m between IK waypoints of a straight move
    move_steps: int = 150  # step cap of one free move
    descend_steps: int = 100  # step cap of one guarded descent
    grip_steps: int = 30  # step cap of closing or opening the fingers
    settle_steps: int = 150  # step cap while waiting for the scene to settle
    settle_min_steps: int = 8  # always step at least this long when settling
    home_joints: tuple[float, ...] = (0.0, -0.3, 0.0, -2.2, 0.0, 1.9, 0.785)  # rad


@dataclass(frozen=True)
class SimConfig:
    """All settings of one physical world."""

    physics: PhysicsConfig = PhysicsConfig()
    layout: LayoutConfig = LayoutConfig()
    control: ControlConfig = ControlConfig()


DEFAULT_CONFIG = SimConfig()

COLOURS: tuple[tuple[float, float, float, float], ...] = (
    (0.85, 0.15, 0.15, 1.0),  # A red
    (0.15, 0.7, 0.2, 1.0),  # B green
    (0.15, 0.3, 0.85, 1.0),  # C blue
    (0.95, 0.8, 0.1, 1.0),  # D yellow
    (0.6, 0.2, 0.75, 1.0),  # E purple
    (0.95, 0.5, 0.1, 1.0),  # F orange
)
