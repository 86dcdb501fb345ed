"""The Franka Panda: inverse kinematics, joint position control and the gripper."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from csql_sim.sim.world.scene import Scene, Vec3, quaternion_from_euler

ARM_JOINTS = (0, 1, 2, 3, 4, 5, 6)
FINGER_JOINTS = (9, 10)
EE_LINK = 11  # panda_grasptarget: between the fingertips
KINEMATIC_BODY = 0  # the arm's body id in the scene's kinematic copy (its only body)
LOWER = (-2.9671, -1.8326, -2.9671, -3.1416, -2.9671, -0.0873, -2.9671)
UPPER = (2.9671, 1.8326, 2.9671, 0.0, 2.9671, 3.8223, 2.9671)

Guard = Callable[[], bool]
YawFit = Callable[[float], "float | None"]
WRIST_YAW = 2.6  # rad: the gripper yaws the arm turns to when it solves IK from its own joints
WRIST_MARGIN = 0.15  # rad: kept from the last joint's limits when the kinematic copy solves IK


def last_joint(home: float, yaw: float, aim: float) -> float:
    """The last joint's angle that turns the downward gripper to ``yaw`` when the base is turned to ``aim``."""
    return home - yaw + aim


def row_fit(yaw: float) -> float | None:
    """``yaw`` if the wrist reaches it with the arm's own IK (|yaw| <= WRIST_YAW), else None."""
    return yaw if abs(yaw) <= WRIST_YAW else None


def polar_path(start: np.ndarray, target: np.ndarray) -> Callable[[float], tuple[np.ndarray, float]]:
    """The arc from ``start`` to ``target`` about the base's axis (radius, angle and height linear in the fraction).

    The returned function maps a fraction of the path to (its point, the path's length so far).
    Angles are taken in (-pi, pi], so the arc never crosses the back of the arm.
    """
    r0, r1 = math.hypot(start[0], start[1]), math.hypot(target[0], target[1])
    a0, a1 = math.atan2(start[1], start[0]), math.atan2(target[1], target[0])
    dz = float(target[2] - start[2])
    total = math.sqrt((r1 - r0) ** 2 + ((r0 + r1) / 2 * (a1 - a0)) ** 2 + dz ** 2)

    def at(frac: float) -> tuple[np.ndarray, float]:
        r, a = r0 + (r1 - r0) * frac, a0 + (a1 - a0) * frac
        return np.array([r * math.cos(a), r * math.sin(a), start[2] + dz * frac]), total * frac

    return at


class Panda:
    """Controller of the scene's Panda (all calls on the scene's own client)."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.body = scene.bodies["panda"]
        self.cc = scene.config.control
        self.yaw = 0.0  # last commanded gripper yaw, rad

    # ------------------------------------------------------------ state

    def ee_position(self) -> np.ndarray:
        """World position of the grasp point between the fingertips."""
        position, _, _ = self.scene.link_state(self.body, EE_LINK)
        return np.array(position)

    def finger_width(self) -> float:
        """Distance between the two fingers, m."""
        return sum(self.scene.joint_positions(self.body, FINGER_JOINTS))

    def finger_contacts(self) -> tuple[set[int], set[int]]:
        """Bodies touching the left and the right finger."""
        return (self.scene.contact_bodies(self.body, FINGER_JOINTS[0]),
                self.scene.contact_bodies(self.body, FINGER_JOINTS[1]))

    def grips(self, body: int) -> bool:
        """True when both fingers touch ``body``."""
        left, right = self.finger_contacts()
        return body in left and body in right

    def touching(self) -> set[int]:
        """Bodies touching any link of the arm or hand."""
        return self.scene.contact_bodies(self.body)

    # ------------------------------------------------------------ motion

    def wrist_fit(self, x: float, y: float) -> YawFit:
        """For a grasp above (x, y): the gripper yaw the wrist reaches for a wanted yaw (None: none).

        Solving IK from its own joints the arm takes |yaw| <= WRIST_YAW (:func:`row_fit`);
        with the kinematic copy (its base turned towards (x, y)) the last joint turns by
        the yaw less that angle, and the same grasp turned by 180 degrees may fit instead.
        """
        if self.scene.kinematics is None:
            return row_fit
        aim = math.atan2(y, x)
        low, high = LOWER[6] + WRIST_MARGIN, UPPER[6] - WRIST_MARGIN

        def fit(yaw: float) -> float | None:
            turns = [yaw + k * math.pi for k in (0, 1, -1, 2, -2)]
            return next((t for t in turns if low <= last_joint(self.cc.home_joints[6], t, aim) <= high), None)

        return fit


    def ik(self, position: Vec3, yaw: float) -> list[float]:
        """Joint angles placing the grasp point at ``position``, pointing down, rotated by ``yaw``.

        Solved from the arm's current joints, or (``ControlConfig.ik_model``) on the scene's
        kinematic copy of the arm, starting from the home pose turned towards the target.
        """
        orn = quaternion_from_euler((math.pi, 0.0, yaw))
        rest = list(self.cc.home_joints)
        rest[6] = self.cc.home_joints[6] + yaw
        ranges = [u - lo for lo, u in zip(LOWER, UPPER, strict=True)]
        model = self.scene.kinematics
        if model is None:
            q = self.scene.inverse_kinematics(self.body, EE_LINK, position, orn, LOWER, UPPER, ranges, rest,
                                              self.cc.ik_iterations, self.cc.ik_threshold)
            return q[:7]
        start = list(self.cc.home_joints)
        start[0] = math.atan2(position[1], position[0])
        start[6] = last_joint(self.cc.home_joints[6], yaw, start[0])
        for j, v in enumerate(start):
            model.reset_joint(KINEMATIC_BODY, j, v)
        q = model.inverse_kinematics(KINEMATIC_BODY, EE_LINK, position, orn, LOWER, UPPER, ranges, rest,
                                     self.cc.ik_model_iterations, self.cc.ik_threshold)[:7]
        q[6] -= 2 * math.pi * round((q[6] - start[6]) / (2 * math.pi))  # the same hand pose, near the start
        return q

    def command_arm(self, q: list[float]) -> None:
        """Set joint position targets (velocity-capped motors)."""
        self.scene.set_joint_targets(self.body, ARM_JOINTS, q, self.cc.arm_forces, self.cc.arm_max_velocity,
                                     position_gain=self.cc.arm_position_gain)

    def joints(self) -> np.ndarray:
        """Current arm joint positions."""
        return np.array(self.scene.joint_positions(self.body, ARM_JOINTS))

    def move_to(self, position: Vec3, yaw: float, speed: float, max_steps: int, guard: Guard | None = None,
                during: Callable[[float], None] | None = None, rest: bool = True) -> str:
        """Drive the grasp point to ``position`` along a smooth joint-space path.

        Args:
            position: target of the grasp point, m.
            yaw: gripper rotation about the vertical, rad.
            speed: mean Cartesian speed of the grasp point, m/s.
            max_steps: step cap, including the final wait for arrival.
            guard: checked every ``check_every`` steps; True stops the motion.
            during: called with the fraction of the path done, at every check.
            rest: wait until the hand is at rest at ``position`` (:meth:`arrived`); False: only
                until it is within ``blend_tolerance`` of it (:meth:`near`), for a motion that
                another one continues.

        Returns:
            ``"reached"``, ``"guard"`` or ``"timeout"``.
        """
        cc = self.cc
        dt = self.scene.config.physics.time_step
        target = np.asarray(position, dtype=float)
        self.yaw = yaw
        start = self.ee_position()
        dist = float(np.linalg.norm(target - start))
        # joint-space waypoints on the path (a line, or an arc about the base), so it does not sag between them
        path = polar_path(start, target) if cc.polar_moves else None
        length = dist if path is None else path(1.0)[1]
        count = max(1, math.ceil(length / cc.waypoint_spacing))
        points = [start + (target - start) * k / count if path is None else path(k / count)[0]
                  for k in range(1, count + 1)]
        qs = [self.joints()] + [np.array(self.ik(tuple(p), yaw)) for p in points]
        joint_dist = float(sum(np.max(np.abs(b - a)) for a, b in zip(qs, qs[1:], strict=False)))
        every = cc.check_every
        duration = max(length / speed, joint_dist / cc.arm_max_velocity, every * dt)
        total = min(every * math.ceil(duration / dt / every), max_steps)
        done = 0
        while done < total:
            frac = min(1.0, (done + every) / total)
            s = (0.5 - 0.5 * math.cos(math.pi * frac)) * count
            k = min(int(s), count - 1)
            self.command_arm(list(qs[k] + (s - k) * (qs[k + 1] - qs[k])))
            self.scene.step(every)
            done += every
            if during is not None:
                during(frac)
            if guard is not None and guard():
                self.hold_here(yaw)
                return "guard"
        self.command_arm(self.ik(position, yaw))
        while done < max_steps:
            if self.arrived(target) if rest else self.near(target):
                return "reached"
            self.scene.step(every)
            done += every
            if guard is not None and guard():
                self.hold_here(yaw)
                return "guard"
        return "timeout"

    def vertical(self, position: Vec3, yaw: float, guard: Guard | None = None) -> str:
        """A descent or a lift to ``position``, returning as :meth:`move_to` does.

        At ``descend_speed``, or (``approach_gap`` > 0) at ``move_speed`` except for the last
        ``approach_gap`` of a descent. With ``blend_tolerance`` > 0 a lift and a descent's
        fast part end without waiting for the hand to come to rest.
        """
        cc = self.cc
        gap = cc.approach_gap
        if gap <= 0:
            return self.move_to(position, yaw, cc.descend_speed, cc.descend_steps, guard)
        z = float(self.ee_position()[2])
        rest = cc.blend_tolerance <= 0
        if position[2] > z:  # a lift
            return self.move_to(position, yaw, cc.move_speed, cc.descend_steps, guard, rest=rest)
        if z - position[2] > 2 * gap:
            fast = self.move_to((position[0], position[1], position[2] + gap), yaw, cc.move_speed, cc.descend_steps,
                                guard, rest=rest)
            if fast == "guard":
                return fast
        return self.move_to(position, yaw, cc.descend_speed, cc.descend_steps, guard)

    def arrived(self, target: np.ndarray) -> bool:
        """Grasp point within reach_tolerance of ``target`` and nearly at rest."""
        position, _, velocity = self.scene.link_state(self.body, EE_LINK, velocity=True)
        return bool(np.linalg.norm(np.subtract(position, target)) < self.cc.reach_tolerance
                    and np.linalg.norm(velocity) < self.cc.arrive_speed)

    def near(self, target: np.ndarray) -> bool:
        """Grasp point within ``blend_tolerance`` of ``target`` (moving or not)."""
        return bool(np.linalg.norm(self.ee_position() - target) < self.cc.blend_tolerance)

    def hold_here(self, yaw: float) -> None:
        """Freeze the arm at its current grasp-point position."""
        self.command_arm(self.ik(tuple(self.ee_position()), yaw))

    def set_fingers(self, width: float) -> None:
        """Command both fingers towards half of ``width`` each."""
        half = width / 2
        self.scene.set_joint_targets(self.body, FINGER_JOINTS, (half,) * len(FINGER_JOINTS),
                                     (self.cc.finger_force,) * len(FINGER_JOINTS), self.cc.finger_max_velocity)

    def close(self, body: int | None) -> bool:
        """Close the fingers; stops once both touch ``body`` and are still. True if they grip it."""
        self.set_fingers(0.0)
        every = self.cc.check_every
        last = self.finger_width()
        for _ in range(0, self.cc.grip_steps, every):
            self.scene.step(every)
            width = self.finger_width()
            if body is not None and self.grips(body) and abs(width - last) < self.cc.grip_still:
                return True
            last = width
        return body is not None and self.grips(body)

    def open(self, width: float | None = None) -> None:
        """Open the fingers to ``width`` (default: fully)."""
        width = 2 * self.cc.finger_open if width is None else min(width, 2 * self.cc.finger_open)
        self.set_fingers(width)
        every = self.cc.check_every
        for _ in range(0, self.cc.grip_steps, every):
            if self.finger_width() > width - 0.004:
                return
            self.scene.step(every)
