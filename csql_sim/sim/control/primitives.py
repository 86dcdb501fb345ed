"""Pick and place primitives with real contact grasping (ravens style).

Each primitive is a small callable: move above, descend with a guard, close or open the
fingers, lift, retreat (the lift ends at the carry height, out of the camera's way).
It returns a :class:`Status`. Nothing attaches a cube to the gripper and no cube pose is
ever set: cubes move only through contact. Step caps count simulation steps.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from csql_sim.core.state.world import Action, ActionKind
from csql_sim.sim.perception.poses import Observation, settled, wrap_quarter
from csql_sim.sim.world.arm_state import letter
from csql_sim.sim.world.layout import putdown_spots, spot_yaw
from csql_sim.sim.world.robot import Panda, YawFit, row_fit
from csql_sim.sim.world.scene import Scene


@dataclass(frozen=True)
class ApproachOffsets:
    """Named offsets of the approach, in metres."""

    carry_clearance: float = 0.05  # held cube bottom / fingertips above the highest cube
    grasp_above_centre: float = 0.002  # grasp point above the cube centre (fingertips clear the cube below)
    grasp_opening_margin: float = 0.025  # fingers open this much wider than a cube before a grasp
    place_gap: float = 0.004  # held cube bottom above its support when released
    descend_stop_early: float = 0.012  # a guard stop further than this from target is a failure


OFFSETS = ApproachOffsets()


@dataclass(frozen=True)
class Status:
    """Outcome of one primitive.

    Attributes:
        ok: True when the motion completed as intended.
        reason: why not, else empty.
        steps: simulation steps the primitive took.
        refused: the action did not start because its preconditions do not hold as sensed
            (a guard's verdict on the observation, or a put with nothing in the gripper).
            Any other failure, even one before the arm moved (no free spot on the table),
            is not a refusal: it says nothing about the preconditions.
    """

    ok: bool
    reason: str = ""
    steps: int = 0
    refused: bool = False


CarryHook = Callable[[float], None]


def carry_height(obs: Observation, exclude: int | None, offsets: ApproachOffsets = OFFSETS) -> float:
    """Grasp-point height that clears every cube except ``exclude`` (the held one)."""
    tops = [b.position[2] + obs.size / 2 for i, b in enumerate(obs.blocks) if i != exclude]
    return max(tops + [0.0]) + obs.size / 2 + offsets.carry_clearance


def carry_level(obs: Observation, exclude: int | None, panda: Panda, x: float, y: float,
                offsets: ApproachOffsets = OFFSETS, margin: float = 0.15) -> float:
    """The grasp point's height for carrying to above (x, y), at most ``carry_ceiling``.

    Above every cube (:func:`carry_height`), or (``ControlConfig.local_carry``) above the
    cubes in the sector the hand sweeps along its arc from where it is to (x, y), widened
    by ``margin`` metres of arc at either end.
    """
    cc = panda.cc
    if not cc.local_carry:
        return min(carry_height(obs, exclude, offsets), cc.carry_ceiling)
    hand = panda.ee_position()
    a0, a1 = math.atan2(hand[1], hand[0]), math.atan2(y, x)
    widen = margin / max(0.1, math.hypot(x, y))
    lo, hi = min(a0, a1) - widen, max(a0, a1) + widen
    tops = [b.position[2] + obs.size / 2 for i, b in enumerate(obs.blocks)
            if i != exclude and lo <= math.atan2(b.position[1], b.position[0]) <= hi]
    return min(max(tops + [0.0]) + obs.size / 2 + offsets.carry_clearance, cc.carry_ceiling)


def rise_to(panda: Panda, z: float) -> None:
    """With ``local_carry``: lift the hand straight up to height ``z`` first, if it is lower.

    The carry's height then holds along the whole arc (it is above the cubes of the arc's
    sector only, and the move interpolates the height from where the hand is).
    """
    hand = panda.ee_position()
    if panda.cc.local_carry and hand[2] < z - 0.002:
        panda.vertical((float(hand[0]), float(hand[1]), z), panda.yaw)


def free_spot(obs: Observation, held: int, scene: Scene, rng: np.random.Generator) -> tuple[float, float] | None:
    """A random table spot at least ``free_clearance`` from every other cube.

    With ``LayoutConfig.shun_housing``, the spots where no tower stands in the forearm
    housing's way (:func:`housing_clear`) are drawn from first, if there are any; with
    ``near_putdown`` the one nearest the held cube is taken (nothing drawn).
    """
    lay = scene.config.layout
    others = [b.position for i, b in enumerate(obs.blocks) if i != held]
    spots = [(x, y) for x, y in putdown_spots(scene.config)
             if all(math.hypot(x - p[0], y - p[1]) >= lay.free_clearance for p in others)]
    if lay.shun_housing:
        bases = [b.position for i, b in enumerate(obs.blocks) if i in scene.tall_bases and i != held]
        spots = shun_housing(spots, others, obs.size, held in scene.tall_bases, bases)
    if not spots:
        return None
    if lay.near_putdown:
        hx, hy = obs.blocks[held].position[:2]
        return min(spots, key=lambda s: math.hypot(s[0] - hx, s[1] - hy))
    return spots[int(rng.integers(len(spots)))]


@dataclass(frozen=True)
class HousingZone:
    """Where the forearm's housing is when the hand is down at the table, in the hand's radial frame, m.

    The housing bulges on the anticlockwise side of the arm's vertical plane, 0.04-0.11 m
    nearer the base than the hand and about 0.18 m above the grasp point.
    """

    radial_near: float = -0.16  # cube centres from this far nearer the base ...
    radial_far: float = 0.0  # ... to the hand's own radius
    lateral: float = 0.16  # and this far anticlockwise of the arm's plane
    height: float = 0.17  # a cube top higher than this above the table is in its way


HOUSING = HousingZone()
ANY_HEIGHT = HousingZone(height=-1.0)
"""The housing's zone for a cube of any height (one that a tower may grow on)."""


def housing_clear(others: list[tuple[float, float, float]], size: float, x: float, y: float,
                  zone: HousingZone = HOUSING) -> bool:
    """No cube in the housing's way when the hand goes down to the table at (x, y)."""
    r = math.hypot(x, y)
    ux, uy = x / r, y / r
    for p in others:
        dx, dy = p[0] - x, p[1] - y
        radial, lateral = dx * ux + dy * uy, -dx * uy + dy * ux
        if zone.radial_near <= radial <= zone.radial_far and 0 < lateral <= zone.lateral \
                and p[2] + size / 2 > zone.height:
            return False
    return True


def shun_housing(spots: list[tuple[float, float]], others: list[tuple[float, float, float]], size: float,
                 base: bool = False, bases: list[tuple[float, float, float]] | None = None
                 ) -> list[tuple[float, float]]:
    """The putdown spots to draw from: the best kind there is, of three.

    Best, a spot where no tall tower is in the housing's way now (:func:`housing_clear`) and
    none may grow there: for the bottom of a tall goal tower (``base``), a spot in no other
    cube's housing way (its tower, grown, would stand beside the hand going down to that
    cube); for any other cube, a spot with no such bottom (``bases``, of any height) in its own
    housing way. Else a spot :func:`housing_clear` now; else all of them. Only the places
    beside the goal's tall towers are given up, so putdowns stay near the hand.
    """
    clear = [s for s in spots if housing_clear(others, size, *s)]
    if base:
        best = [s for s in clear if all(housing_clear([(*s, 1.0)], size, p[0], p[1]) for p in others)]
    else:
        best = [s for s in clear if housing_clear(bases or [], size, *s, zone=ANY_HEIGHT)]
    return best or clear or spots


@dataclass(frozen=True)
class HandFootprint:
    """Boxes swept by the open hand around the grasp point (in the closing-axis frame), m."""

    hand_half_length: float = 0.11  # palm half extent along the closing axis
    hand_half_width: float = 0.035  # palm half extent across it
    hand_bottom: float = 0.035  # palm underside above the grasp point
    finger_thickness: float = 0.032  # finger outer face beyond its inner face (with collision margin)
    finger_half_width: float = 0.012  # finger half extent across the axis
    finger_tip: float = 0.012  # fingertips below the grasp point
    margin: float = 0.004  # extra room around every box


FOOTPRINT = HandFootprint()


def _conflicts(obs: Observation, x: float, y: float, z: float, yaw: float, exclude: set[int], opening: float,
               fp: HandFootprint = FOOTPRINT) -> int:
    """Cubes the open hand would hit at grasp point (x, y, z) with closing axis at ``yaw``."""
    half = obs.size / 2
    reach = half + fp.margin  # a cube's half size plus margin
    axis = (-math.sin(yaw), math.cos(yaw))  # fingers close along the hand's y axis
    hits = 0
    for i, b in enumerate(obs.blocks):
        if i in exclude:
            continue
        dx, dy = b.position[0] - x, b.position[1] - y
        along = abs(dx * axis[0] + dy * axis[1])
        across = abs(-dx * axis[1] + dy * axis[0])
        top = b.position[2] + half
        palm = top > z + fp.hand_bottom - fp.margin and along < fp.hand_half_length + reach \
            and across < fp.hand_half_width + reach
        finger = top > z - fp.finger_tip - fp.margin and along < opening / 2 + fp.finger_thickness + reach \
            and across < fp.finger_half_width + reach
        hits += palm or finger
    return hits


def choose_yaw(obs: Observation, x: float, y: float, z: float, cube_yaw: float, current: float,
               exclude: set[int], opening: float, attempt: int = 0, fit: YawFit = row_fit) -> float:
    """A gripper yaw aligned with a cube face (three choices, 90 degrees apart).

    Ranked by the cubes the open hand would hit, then by wrist rotation; ``attempt``
    k > 0 (a retry after a failed grasp of the same cube) takes the next choice. ``fit``
    keeps the wrist inside its range (:meth:`~csql_sim.sim.world.robot.Panda.wrist_fit`).
    """
    base = current + wrap_quarter(cube_yaw - current)
    options = [base, base + math.pi / 2, base - math.pi / 2]
    options = [f for f in map(fit, options) if f is not None]
    ranked = sorted(options, key=lambda o: (_conflicts(obs, x, y, z, o, exclude, opening), abs(o - current)))
    return ranked[attempt % len(ranked)]


class Pick:
    """Pick a cube up (pickup from the table and unstack from a cube move alike)."""

    def __init__(self, block: int, offsets: ApproachOffsets = OFFSETS, attempt: int = 0) -> None:
        self.block = block
        self.offsets = offsets
        self.attempt = attempt  # retries of this grasp so far: each tries the next gripper yaw

    def __call__(self, scene: Scene, panda: Panda, obs: Observation, rng: np.random.Generator,
                 carry_hook: CarryHook | None = None) -> Status:
        start = scene.steps
        cc = scene.config.control
        body = scene.block_body(self.block)
        target = obs.blocks[self.block]
        x, y, z = target.position
        goal_z = z + self.offsets.grasp_above_centre
        opening = obs.size + self.offsets.grasp_opening_margin
        yaw = choose_yaw(obs, x, y, goal_z, target.yaw, panda.yaw, {self.block}, opening, self.attempt,
                         panda.wrist_fit(x, y))
        high = carry_level(obs, None, panda, x, y, self.offsets)
        panda.open(opening)
        rise_to(panda, high)
        panda.move_to((x, y, high), yaw, cc.move_speed, cc.move_steps)
        arrived = panda.vertical((x, y, goal_z), yaw, guard=lambda: bool(panda.touching() - {body}))
        if arrived == "guard" and panda.ee_position()[2] - goal_z > self.offsets.descend_stop_early:
            panda.vertical((x, y, high), yaw)
            return Status(False, f"collision while descending onto {letter(self.block)}", scene.steps - start)
        if not panda.close(body):
            panda.open()
            panda.vertical((x, y, high), yaw)
            return Status(False, f"grasp of {letter(self.block)} missed", scene.steps - start)
        panda.vertical((x, y, high), yaw)
        if not panda.grips(body):
            return Status(False, f"{letter(self.block)} slipped out while lifting", scene.steps - start)
        return Status(True, "", scene.steps - start)


class Place:
    """Put the held cube on the table (``onto`` None) or on another cube."""

    def __init__(self, block: int, onto: int | None, offsets: ApproachOffsets = OFFSETS) -> None:
        self.block = block
        self.onto = onto
        self.offsets = offsets

    def __call__(self, scene: Scene, panda: Panda, obs: Observation, rng: np.random.Generator,
                 carry_hook: CarryHook | None = None) -> Status:
        start = scene.steps
        cc = scene.config.control
        size = obs.size
        body = scene.block_body(self.block)
        if not panda.grips(body):
            return Status(False, f"{letter(self.block)} is not in the gripper", 0, refused=True)
        held = obs.blocks[self.block]
        gp = np.asarray(obs.grasp_point)
        offset = np.asarray(held.position[:2]) - gp[:2]  # where the cube hangs relative to the grasp point
        relative = wrap_quarter(held.yaw - panda.yaw)  # cube yaw in the gripper
        hang = gp[2] - held.position[2]  # grasp point above the cube centre
        if not held.visible:  # unread in the hand (known there by elimination): it hangs as it was grasped
            offset, relative, hang = np.zeros(2), 0.0, self.offsets.grasp_above_centre
        if self.onto is None:
            spot = free_spot(obs, self.block, scene, rng)
            if spot is None:
                return Status(False, "no free spot on the table", 0)  # not a refusal: holding(x) holds
            tx, ty, support_top = spot[0], spot[1], 0.0
            want = spot_yaw(scene.config, tx, ty, held.yaw)
        else:
            below = obs.blocks[self.onto]
            tx, ty = below.position[0], below.position[1]
            if cc.aim_column:
                tx, ty = column_centre(obs, self.onto, self.block)
            support_top = below.position[2] + size / 2
            want = below.yaw
        goal_z = support_top + size / 2 + self.offsets.place_gap + hang
        yaw = choose_yaw(obs, tx, ty, goal_z, want - relative, panda.yaw, {self.block, self.onto}, size,
                         fit=panda.wrist_fit(tx, ty))
        turn = yaw - panda.yaw
        c, s = math.cos(turn), math.sin(turn)
        offset = np.array([c * offset[0] - s * offset[1], s * offset[0] + c * offset[1]])
        x, y = tx - offset[0], ty - offset[1]
        high = carry_level(obs, self.block, panda, x, y, self.offsets)
        rise_to(panda, high)
        panda.move_to((x, y, high), yaw, cc.move_speed, cc.move_steps, during=carry_hook)
        if not panda.grips(body):
            return Status(False, f"{letter(self.block)} dropped during the carry", scene.steps - start)
        others = {scene.bodies["table"]} | {scene.block_body(i) for i in range(scene.n) if i != self.block}
        if cc.place_pause > 0:  # come to rest just above: the hand trails its path while it moves
            panda.vertical((x, y, goal_z + cc.place_pause), yaw)
        panda.vertical((x, y, goal_z), yaw, guard=lambda: bool(scene.contact_bodies(body) & others))
        panda.open(size + cc.release_opening if cc.release_opening > 0 else None)
        panda.vertical((x, y, high), yaw)
        settle(scene, panda)
        return Status(True, "", scene.steps - start)


def column_centre(obs: Observation, top: int, held: int, reach: float = 0.022) -> tuple[float, float]:
    """The mean xy of cube ``top`` and the cubes under it (those within ``reach`` of it horizontally, lower).

    Aiming a stack there, not at the top cube alone, keeps a small error of each placement
    (the camera's estimate, the hand's) from adding up level by level into a leaning tower.
    """
    t = obs.blocks[top].position
    column = [b.position for i, b in enumerate(obs.blocks) if i != held and b.visible
              and math.hypot(b.position[0] - t[0], b.position[1] - t[1]) < reach and b.position[2] <= t[2] + 1e-6]
    return float(np.mean([p[0] for p in column])), float(np.mean([p[1] for p in column]))


def settle(scene: Scene, panda: Panda) -> int:
    """Step until every free cube is at rest (or the settle cap); returns steps taken."""
    cc = scene.config.control
    start = scene.steps
    scene.step(cc.settle_min_steps)
    while scene.steps - start < cc.settle_steps and not settled(scene, panda):
        scene.step(cc.check_every)
    return scene.steps - start


def primitive_for(action: Action, offsets: ApproachOffsets = OFFSETS, attempt: int = 0) -> Pick | Place:
    """The primitive that executes ``action``."""
    if action.kind in (ActionKind.PICKUP, ActionKind.UNSTACK):
        return Pick(action.block, offsets, attempt)
    if action.kind is ActionKind.PUTDOWN:
        return Place(action.block, None, offsets)
    return Place(action.block, action.target, offsets)
