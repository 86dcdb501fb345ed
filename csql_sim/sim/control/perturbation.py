"""What ``--perturb`` does to a physical episode: a jittered start, a nudge, a dropped cube.

Every draw comes from the episode's generator. A nudge pushes a clear cube sideways with
an external force for a few steps (physics, never a reset); a drop opens the gripper early
in a carry, where the cube falls clear of the others. :class:`PerturbationPlan` says
before which action each strikes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csql_sim.core.state.world import Action
from csql_sim.sim.control.physical import PhysicalWorld
from csql_sim.sim.control.primitives import CarryHook
from csql_sim.sim.world.arm_state import letter


@dataclass(frozen=True)
class Perturbation:
    """What --perturb does to an episode (all draws from the episode's generator)."""

    jitter_start: bool = True  # offset and rotate every cube of the start scene
    nudge_probability: float = 0.5  # chance of one physical nudge before some action
    nudge_force: float = 3.0  # N, horizontal, at the cube's centre
    nudge_steps: int = 10  # steps the force acts
    drop_probability: float = 0.5  # chance of opening the gripper during one carry
    drop_window: tuple[float, float] = (0.02, 0.1)  # fractions of the carry (arm still slow) to open in
    drop_clearance: float = 0.12  # m: open only where the cube falls clear of other cubes


PERTURBATION = Perturbation()


@dataclass(frozen=True)
class PerturbationPlan:
    """Before which action (by its index in the episode) a nudge or a drop happens; -1: never."""

    nudge_at: int = -1
    drop_at: int = -1

    @classmethod
    def draw(cls, rng: np.random.Generator, optimal: int, perturbation: Perturbation) -> PerturbationPlan:
        """Draw the plan from the episode's generator (nudge first, then drop)."""
        nudge_at = drop_at = -1
        if rng.random() < perturbation.nudge_probability:
            nudge_at = int(rng.integers(max(1, optimal)))
        if rng.random() < perturbation.drop_probability:
            drop_at = int(rng.integers(max(1, optimal)))
        return cls(nudge_at=nudge_at, drop_at=drop_at)


def nudge(world: PhysicalWorld, rng: np.random.Generator, pert: Perturbation) -> str:
    """Push a clear cube sideways with an external force (physics, not a reset).

    A lone cube slides; a cube on top of a tower may be pushed off it onto the table.
    """
    state = world.perceive().state
    if state is None:
        return "nudge skipped: nothing perceived"
    lone = [i for i in range(state.n) if state.is_clear(i)]
    if not lone:
        return "nudge skipped: no clear cube"
    block = lone[int(rng.integers(len(lone)))]
    scene = world.scene
    pos = np.asarray(scene.block_pose(block).position)
    others = [np.asarray(scene.block_pose(i).position) for i in range(state.n) if i != block]
    nearest = min(others, key=lambda p: float(np.linalg.norm(p[:2] - pos[:2])))
    away = math.atan2(pos[1] - nearest[1], pos[0] - nearest[0])
    angle = away + rng.uniform(-math.pi / 4, math.pi / 4)
    force = (pert.nudge_force * math.cos(angle), pert.nudge_force * math.sin(angle), 0.0)
    body = scene.block_body(block)
    for _ in range(pert.nudge_steps):
        centre = scene.block_pose(block).position
        scene.apply_force(body, force, centre)
        scene.step()
    world.settle()
    return f"nudged {letter(block)} towards {math.degrees(angle):.0f} deg"


def drop_hook(world: PhysicalWorld, action: Action, pert: Perturbation, events: list[str]) -> CarryHook | None:
    """A carry hook that opens the gripper once the carried cube is clear of the others."""
    if action.is_pick:
        return None
    scene, panda = world.scene, world.panda
    fired = [False]

    def hook(fraction: float) -> None:
        if fired[0] or not pert.drop_window[0] <= fraction <= pert.drop_window[1]:
            return
        pos = np.asarray(scene.block_pose(action.block).position)
        for i in range(scene.n):
            if i != action.block and np.linalg.norm(np.asarray(scene.block_pose(i).position)[:2] - pos[:2]) < \
                    pert.drop_clearance:
                return
        panda.set_fingers(2 * scene.config.control.finger_open)
        fired[0] = True
        events.append(f"gripper opened while carrying {letter(action.block)}")

    return hook


__all__ = ["PERTURBATION", "Perturbation", "PerturbationPlan", "drop_hook", "nudge"]
