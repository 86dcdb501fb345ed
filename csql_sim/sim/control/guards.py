"""Guards: a primitive checks, on the observation, that its action can start at all.

Discovery attempts actions whose preconditions may not hold. Before any motion the
guarded primitive looks at the observation (cube poses from perception and the finger
opening) and refuses, with a failure :class:`~csql_sim.sim.control.primitives.Status` of zero
steps marked ``refused``, when there is nothing to grasp where the action expects the
cube, something sits on top of the cube to grasp or of the cube to stack onto, or the
hand is already full. Nothing held to put down is noticed by
:class:`~csql_sim.sim.control.primitives.Place` itself (the fingers do not touch the cube), also
as a refusal. No other failure is a refusal, not even one before the arm moved (a
putdown that finds no free spot on the table): it says nothing about the preconditions.
After a put, the guarded primitive checks that the cube came to rest where the action
puts it. Guards never read the symbolic state.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from csql_sim.core.state.world import Action, ActionKind
from csql_sim.sim.control.primitives import CarryHook, Pick, Place, Status
from csql_sim.sim.perception.poses import Observation, Tolerances, gripper_closed_on_cube, holding, on, on_table
from csql_sim.sim.world.arm_state import letter
from csql_sim.sim.world.robot import Panda
from csql_sim.sim.world.scene import Scene


def _on_top_of(obs: Observation, x: int, tol: Tolerances) -> int | None:
    """A cube resting on cube x, if any."""
    return next((y for y in range(len(obs.blocks)) if y != x and on(obs, y, x, tol)), None)


def refusal(action: Action, obs: Observation, tol: Tolerances) -> str:
    """Why ``action``'s primitive must not start in ``obs``; empty when it may."""
    x = action.block
    name = letter(x)
    if action.is_pick:
        if gripper_closed_on_cube(obs, tol) or any(holding(obs, i, tol) for i in range(len(obs.blocks))):
            return "hand already full"
        if action.kind is ActionKind.PICKUP and not on_table(obs, x, tol):
            return f"nothing to grasp: {name} is not on the table"
        if action.kind is ActionKind.UNSTACK and not on(obs, x, action.target, tol):
            return f"nothing to grasp: {name} is not on {letter(action.target)}"
        top = _on_top_of(obs, x, tol)
        if top is not None:
            return f"{letter(top)} is on top of {name}"
    elif action.kind is ActionKind.STACK:
        top = _on_top_of(obs, action.target, tol)
        if top is not None:
            return f"{letter(top)} is on top of {letter(action.target)}"
    return ""


def missed_outcome(action: Action, obs: Observation, tol: Tolerances) -> str:
    """Why a put that reported success did not leave its cube where it should; empty if it did."""
    x = action.block
    if action.kind is ActionKind.PUTDOWN and not on_table(obs, x, tol):
        return f"{letter(x)} did not come to rest on the table"
    if action.kind is ActionKind.STACK and not on(obs, x, action.target, tol):
        return f"{letter(x)} did not come to rest on {letter(action.target)}"
    return ""


@dataclass(frozen=True)
class Guarded:
    """A primitive behind its guard: refuses before moving when :func:`refusal` says so.

    After a put that reported success it also looks once more (the primitive has let the
    scene settle) and reports a failure when the cube did not come to rest where the action
    puts it, e.g. slid off a cube that a nudge had left at an angle. A pick checks its own
    outcome (the cube must stay in the fingers while lifting).
    """

    primitive: Pick | Place
    action: Action
    tol: Tolerances
    observe: Callable[[], Observation] | None = None  # for the check after a put

    def __call__(self, scene: Scene, panda: Panda, obs: Observation, rng: np.random.Generator,
                 carry_hook: CarryHook | None = None) -> Status:
        why = refusal(self.action, obs, self.tol)
        if why:
            return Status(False, why, 0, refused=True)
        status = self.primitive(scene, panda, obs, rng, carry_hook)
        if status.ok and self.observe is not None:
            missed = missed_outcome(self.action, self.observe(), self.tol)
            if missed:
                return Status(False, missed, status.steps)
        return status
