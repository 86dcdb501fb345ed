"""Named constants of the physical world: geometry, physics, control, tolerances."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace


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
    sleep_threshold: float = 0.0  # > 0: Bullet lets a cube sleep after 2 s below this motion, (m/s)^2 + (rad/s)^2


@dataclass(frozen=True)
class LayoutConfig:
    """Where towers of the start scene stand and where putdown may place a block.

    Two shapes: a row (``arc_radius`` 0: start towers along y at ``tower_x``, putdown
    spots on the ``free_x`` x ``free_y`` grid), or an arc (``arc_radius`` > 0: start
    towers and putdown spots alike on ``arc_positions`` places ``arc_spacing`` apart on a
    circle about the arm's base, so the forearm reaching one never sweeps over another).
    """

    tower_x: float = 0.5  # x of the start towers, m
    tower_spacing: float = 0.12  # y distance between start towers, m
    arc_radius: float = 0.0  # > 0: the arc layout's distance from the arm's base (z axis), m
    arc_spacing: float = 0.095  # distance between neighbouring places on the arc, m
    arc_positions: int = 11  # places on the arc (start slots and putdown spots), centred on the x axis
    free_x: tuple[float, ...] = (0.42, 0.50, 0.58)  # candidate putdown x, m
    free_y: tuple[float, ...] = (-0.24, -0.18, -0.12, -0.06, 0.0, 0.06, 0.12, 0.18, 0.24)  # m
    free_clearance: float = 0.085  # min xy distance of a putdown spot from any block, m
    tower_gap: int = 1  # start towers stand on the arc's middle places this many places apart (fewer if they must)
    shun_housing: bool = False  # putdowns prefer spots where no tall tower stands in the forearm housing's way
    near_putdown: bool = False  # a putdown takes the free spot nearest the hand (else a random one)
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
    grip_still: float = 1e-4  # closed on a cube: the finger width changed by less than this between checks, m
    release_opening: float = 0.0  # > 0: a place opens the fingers this much wider than the cube, not fully, m
    settle_steps: int = 150  # step cap while waiting for the scene to settle
    settle_min_steps: int = 8  # always step at least this long when settling
    home_joints: tuple[float, ...] = (0.0, -0.3, 0.0, -2.2, 0.0, 1.9, 0.785)  # rad
    start_joints: tuple[float, ...] | None = None  # the arm's pose when the scene is built (None: home_joints)
    ik_model: bool = False  # solve IK on a kinematic copy of the arm, from the home pose turned to the target
    ik_model_iterations: int = 300  # IK iterations on that copy (it starts from the home pose every time)
    place_pause: float = 0.0  # > 0: a place stops this far above its goal before the last guarded descent, m
    aim_column: bool = False  # stack onto the mean xy of the tower below, not onto its top cube alone
    polar_moves: bool = False  # free moves follow an arc about the base (radius and angle linear), not a line
    carry_ceiling: float = 1.0  # the grasp point is never carried higher than this, m
    approach_gap: float = 0.0  # > 0: descents go at move_speed to this far above their goal, and lifts too, m
    local_carry: bool = False  # carry above the cubes along the way (an arc's sector), not above every cube
    blend_tolerance: float = 0.0  # > 0: lifts and a descent's fast part end this near their goal, moving or not, m


@dataclass(frozen=True)
class SimConfig:
    """All settings of one physical world."""

    physics: PhysicsConfig = PhysicsConfig()
    layout: LayoutConfig = LayoutConfig()
    control: ControlConfig = ControlConfig()


DEFAULT_CONFIG = SimConfig()

MAX_ARM_BLOCKS = 30
"""The most cubes on the arm: the ring of :data:`RING_LAYOUT` has a place for each of 30."""

WIDE_LAYOUT = LayoutConfig(arc_radius=0.64, arc_spacing=0.16, arc_positions=10)
"""The layout of 7..10 cubes: ten places 0.16 m apart on an arc 0.64 m from the arm's base (+-64 degrees).

Ten start towers fit side by side, and with one cube in the hand at most nine places are
taken, so a putdown always finds one. A row would not do: a tower of seven or more
cubes in front of or behind a place is in the forearm's way when the hand goes down there.
On the arc a tall neighbour stands beside the forearm's plane instead: 0.16 m keeps the
forearm's housing (its widest part, on the anticlockwise side) clear of a tower of ten
when the hand goes down to the table next to it, with room for the centimetre by which
such a tower leans (at 0.14 m the housing cleared an upright tower by 12 mm and still
toppled a leaning one)."""

WIDE_PHYSICS = PhysicsConfig(table_half_extents=(0.45, 0.72, 0.02))
"""The table of 7..10 cubes: wider (y within +-0.72 m), so the arc's ends are 0.14 m from its edge."""

WIDE_CONFIG = SimConfig(physics=WIDE_PHYSICS, layout=WIDE_LAYOUT,
                        control=ControlConfig(ik_model=True, move_steps=300, place_pause=0.012,
                                              aim_column=True))
"""The settings of a scene of 7..10 cubes (:func:`config_for`).

Its arm solves inverse kinematics on a kinematic copy of itself, always from the home pose
turned towards the target (``ControlConfig.ik_model``): every solution keeps the elbow up
in the vertical plane through the target, so the forearm going down next to a tall tower
stays clear of it. Solved from the arm's current joints instead (the six-cube setting),
the redundant joints drift over a long episode and the forearm swings sideways into
neighbouring towers. A free move may take 300 steps: from one end of the arc to the other
the base turns by two radians. A place comes to rest 12 mm above its goal before the last
guarded descent: at full reach the moving hand trails its path by about 3 mm towards the
base, and a descent stopped by the contact left every cube of a tall tower that much
further in (a tower of ten leaned by 2 cm). A stack aims at the middle of the tower below,
not at its top cube: the camera's estimates lie 1.5 mm towards it, and aiming at each top
cube in turn added that up level by level too."""


RING_LAYOUT = LayoutConfig(arc_radius=0.5, arc_spacing=0.5 * math.radians(300) / 29, arc_positions=30,
                           free_clearance=0.08, tower_gap=2,
                           shun_housing=True, near_putdown=True)
"""The layout of 11..30 cubes: thirty places on a ring 0.5 m about the arm's base, 300 degrees of it
(+-150 degrees, 10.3 degrees and 90 mm apart), the table reaching behind the arm.

Why a ring this close: a tower of fifteen 4 cm cubes is 0.6 m high, and taking it apart
carries the top cube at 0.67 m; the Panda holds the hand pointing down that high only
within about 0.5 m of its base (0.4 mm off at 0.5 m, 6 mm at 0.55 m). Why one ring: a
hand going down to the table on an outer ring puts the forearm 0.2-0.4 m above the inner
ring, where a tower of five or more stands in its way. Why 90 mm: the open hand closes
along the ring's radius (70 mm wide across it), and the forearm's housing, on the
anticlockwise side of the arm, stays 5 mm clear of an upright tower of fifteen on the
next place. Start towers stand on every other place, from the middle of the ring (every
place past fifteen towers): two places apart, no tower is in the housing's way when the
hand goes down next to another, and the hand goes back and forth between them a short way."""

RING_PHYSICS = PhysicsConfig(table_half_extents=(0.62, 0.62, 0.02), table_centre=(0.0, 0.0, -0.02),
                             solver_iterations=200, sleep_threshold=1e-3)
"""The physics of 11..30 cubes: a square table about the arm's base, its edge 0.12 m beyond the
ring, and 200 solver iterations: at 50 a tower of eleven swayed by itself until it fell, at
100 one of fourteen; at 200 towers of fifteen to seventeen stand (eighteen sway).

Resting cubes may sleep (Bullet's own deactivation): at 200 iterations thirty cubes awake cost
about 8 ms a step, a tower of thirteen alone 2.5 ms, everything asleep 0.1 ms. Resting towers
move by less than 1e-5 (squared m/s and rad/s); the threshold, 1e-3, is far above that and far
below a cube that tips or slides. The hand, a moving cube, a force or a teleport wakes a cube."""

RING_CONFIG = SimConfig(physics=RING_PHYSICS, layout=RING_LAYOUT,
                        control=ControlConfig(ik_model=True, move_steps=700, descend_steps=300, place_pause=0.012,
                                              aim_column=True, polar_moves=True, carry_ceiling=0.69,
                                              move_speed=1.2, approach_gap=0.05, blend_tolerance=0.01,
                                              grip_still=5e-4, release_opening=0.025,
                                              start_joints=(0.0, -0.494, 0.0, -1.36, 0.0, 0.866, 0.785),
                                              local_carry=True))
"""The settings of a scene of 11..30 cubes (:func:`config_for`): :data:`WIDE_CONFIG`'s control,
and free moves along arcs about the base (a straight line between two places across the ring
would pass over the arm's base). A move may take 700 steps: from one end of the ring to the
other the base turns by 5.2 radians. The hand is never carried higher than 0.69 m (the reach at
0.5 m). Descents and lifts go at the free moves' speed (1.2 m/s) up to 5 cm above their goal,
and only the last 5 cm at the guarded descent's speed: the hand goes up and down by as much as
0.65 m, and at 0.45 m/s all the way an action took over 2 s of simulated time. A descent may
take 300 steps. The arm starts with the hand 0.75 m above the table, 0.25 m from its base
(inside the ring, above a tower of fifteen): the home pose of fewer cubes holds the hand 0.4 m
high at 0.46 m, where a start tower of ten would stand. The hand is carried above the cubes
along its arc (``local_carry``), not above the tallest tower anywhere, and a putdown takes the
free place nearest the hand: on a ring this large both halve the way the hand goes.

Less waiting: a lift, and a descent's fast part, hand over to the next motion 1 cm from their
goal without waiting for the hand to stop (``blend_tolerance``); the fingers count as closed on
a cube when they close by less than 0.5 mm in four steps (they go on squeezing it by 0.1 mm at
a time for as long as one waits, so waiting for less takes the whole grip cap); a place opens
them 25 mm wider than the cube, not fully. With camera perception and sensor noise these cut the
simulated time per action of the first 20 tall-tower tasks of seed 0 from 1.61 s to 1.44 at 30
cubes (the earlier settings: :data:`WAITING_CONTROL`; figures in ``docs/results/arm.md``)."""

WAITING_CONTROL = replace(RING_CONFIG.control, approach_gap=0.1, blend_tolerance=0.0, grip_still=1e-4,
                          release_opening=0.0)
"""The ring's earlier control, to compare with: every lift and descent comes to rest, the slow
part of a descent is its last 10 cm, a grasp waits the whole grip cap, and a place opens the
fingers fully (``benchmarks/arm_thirty.py --waiting``)."""

MAX_TOWER_HEIGHT = 15
"""The tallest tower a task may need on :data:`RING_LAYOUT`; a task whose start, goal or plan
needs a taller one is refused.

Measured (``benchmarks/arm_thirty.py --towers 15,16,17``, GN1, pose perception): towers of
15, 16 and 17 cubes built from the table and taken apart again, each alone in its scene.
Fifteen is the limit because a hand carrying a cube must also pass over the towers between
two places: under the reach's ceiling (0.69 m) the carried cube clears a tower of fifteen by
the full 5 cm, one of sixteen by 2.8 cm, and cannot pass over one of seventeen. (Eighteen
sways by itself until it falls, at 200 solver iterations.)"""


def config_for(n: int) -> SimConfig:
    """The settings of n cubes: :data:`DEFAULT_CONFIG` (n <= 6), :data:`WIDE_CONFIG`, :data:`RING_CONFIG` (n > 10)."""
    if n <= 6:
        return DEFAULT_CONFIG
    return WIDE_CONFIG if n <= 10 else RING_CONFIG


COLOURS: tuple[tuple[float, float, float, float], ...] = (
    (0.85, 0.15, 0.15, 1.0),  # A red, hue 0
    (0.15, 0.7, 0.2, 1.0),  # B green, hue 126
    (0.15, 0.3, 0.85, 1.0),  # C blue, hue 227
    (0.95, 0.8, 0.1, 1.0),  # D yellow, hue 49
    (0.6, 0.2, 0.75, 1.0),  # E purple, hue 284
    (0.95, 0.5, 0.1, 1.0),  # F orange, hue 28
    (0.1, 0.75, 0.85, 1.0),  # G cyan, hue 188
    (0.9, 0.15, 0.6, 1.0),  # H magenta, hue 324
    (0.55, 0.85, 0.1, 1.0),  # I lime, hue 84
    (0.1, 0.65, 0.45, 1.0),  # J teal, hue 158
)
"""The cubes' paint, cosmetic: cubes are told apart by their printed markers
(:mod:`csql_sim.sim.world.markers`), so past ten the paints repeat (:func:`cube_colour`)."""
COLOUR_NAMES: tuple[str, ...] = ("red", "green", "blue", "yellow", "purple", "orange", "cyan", "magenta", "lime",
                                 "teal")
"""The paints' names, in the order of :data:`COLOURS` (cube A red, B green, ...): the legend's words."""


def cube_colour(i: int) -> tuple[float, float, float, float]:
    """The paint of cube ``i``: :data:`COLOURS` in turn, again from the first past ten."""
    return COLOURS[i % len(COLOURS)]


def colour_name(i: int) -> str:
    """The word of cube ``i``'s paint (:func:`cube_colour`)."""
    return COLOUR_NAMES[i % len(COLOUR_NAMES)]
