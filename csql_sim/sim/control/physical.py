"""One physical blocks world: scene, arm, perception and primitives behind a small API."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from csql_sim.core.model.task import Task
from csql_sim.core.state.world import Action
from csql_sim.sim.control.guards import Guarded
from csql_sim.sim.control.primitives import CarryHook, Pick, Status, primitive_for, settle
from csql_sim.sim.control.recovery import Drag, recovery_for
from csql_sim.sim.perception.camera import CAMERA_TOLERANCES, Camera, fallback_cameras, perception_cameras
from csql_sim.sim.perception.poses import (
    TOLERANCES,
    Observation,
    Perceived,
    Tolerances,
    interpret,
    observe_poses,
    settled,
)
from csql_sim.sim.perception.rgbd import NO_NOISE, CameraNoise, observe_rgbd
from csql_sim.sim.world.arm_state import ArmState, SimError, check_arm_blocks, letter
from csql_sim.sim.world.config import SimConfig, config_for
from csql_sim.sim.world.layout import place_towers
from csql_sim.sim.world.robot import Panda
from csql_sim.sim.world.scene import Pose, Scene
from csql_sim.sim.world.tower_height import tall_bases

PERCEPTION_MODES = ("pose", "camera")


def check_perception(perception: str, n: int | None = None) -> str:
    """``perception`` if it is one of :data:`PERCEPTION_MODES`.

    ``n`` is accepted for the callers' sake: the camera tells every one of the arm's cubes apart by
    its printed marker (:mod:`csql_sim.sim.world.markers`), so no number of cubes is refused here.

    Raises:
        SimError: for any other mode.
    """
    if perception not in PERCEPTION_MODES:
        raise SimError(f"perception must be one of {', '.join(PERCEPTION_MODES)}, got {perception!r}")
    return perception


class GoalTest(Protocol):
    """A partial goal: says whether a perceived state satisfies it (``None``: nothing perceived)."""

    def satisfied(self, state: ArmState | None) -> bool:
        """Whether ``state`` satisfies the goal."""
        ...


@dataclass
class PhysicalWorld:
    """A scene with its Panda, the seeded generator and a perception mode.

    Args:
        n: number of cubes, 2..30; states are :class:`~csql_sim.core.state.state.State` records.
        seed: seeds the one generator used for putdown spots and perturbations.
        perception: ``"pose"`` (body poses) or ``"camera"`` (colour + depth images, rgbd.py).
        config: scene settings (default: :func:`~csql_sim.sim.world.config.config_for` n).
        cameras: the perception cameras (default: :func:`~csql_sim.sim.perception.camera.perception_cameras` n).
        camera_noise: sensor noise of camera perception; drawn from a generator of its
            own (spawned from ``seed``), so noise never shifts the episode's other draws.
        fallback: views rendered only while a cube is unread by ``cameras`` (default:
            :func:`~csql_sim.sim.perception.camera.fallback_cameras` n).
    """

    n: int
    seed: int = 0
    perception: str = "pose"
    config: SimConfig | None = None  # None: config_for(n), set in __post_init__
    cameras: tuple[Camera, ...] | None = None  # None: perception_cameras(n), set in __post_init__
    camera_noise: CameraNoise = NO_NOISE
    fallback: tuple[Camera, ...] | None = None  # None: fallback_cameras(n), set in __post_init__
    scene: Scene = field(init=False)
    panda: Panda = field(init=False)
    rng: np.random.Generator = field(init=False)
    sensor_rng: np.random.Generator = field(init=False)
    _seen: tuple[int, Observation] | None = field(init=False, default=None)  # (scene step, observation)

    def __post_init__(self) -> None:
        check_perception(self.perception, self.n)
        check_arm_blocks(self.n)
        self.config = config_for(self.n) if self.config is None else self.config
        self.cameras = perception_cameras(self.n) if self.cameras is None else self.cameras
        self.fallback = fallback_cameras(self.n) if self.fallback is None else self.fallback
        self.scene = Scene(self.n, self.config)
        self.panda = Panda(self.scene)
        self.rng = np.random.default_rng(self.seed)
        self.sensor_rng = np.random.default_rng(np.random.SeedSequence(self.seed).spawn(1)[0])

    def close(self) -> None:
        """Release the physics client."""
        self.scene.close()

    def __enter__(self) -> PhysicalWorld:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def build(self, state: ArmState, jitter: bool = False) -> None:
        """Build ``state``: place the towers, settle, and grasp a held block for real.

        Raises:
            SimError: if the world has another number of blocks or the grasp fails.
        """
        if state.n != self.n:
            raise SimError(f"state {state.notation()} has {state.n} blocks, the scene {self.n}")
        place_towers(self.scene, state, self.rng, jitter=jitter)
        self._seen = None
        settle(self.scene, self.panda)
        held = state.held
        if held is not None:
            status = Pick(held)(self.scene, self.panda, self.observe(), self.rng)
            if not status.ok:
                raise SimError(f"could not build {state.notation()}: {status.reason}")
            settle(self.scene, self.panda)

    def expect(self, goal: ArmState) -> None:
        """Tell putdowns the goal's tall towers: the places beside their bottoms are kept clear (``shun_housing``)."""
        self.scene.tall_bases = tall_bases(goal)

    def observe(self) -> Observation:
        """An observation in the configured perception mode (one per simulation step: nothing moved since)."""
        if self._seen is not None and self._seen[0] == self.scene.steps:
            return self._seen[1]
        if self.perception == "camera":
            obs = observe_rgbd(self.scene, self.panda, self.cameras, self.camera_noise, self.sensor_rng,
                               self.fallback)
        else:
            obs = observe_poses(self.scene, self.panda)
        self._seen = (self.scene.steps, obs)
        return obs

    def perceive(self) -> Perceived:
        """Settle, observe and interpret the scene."""
        self.settle()
        return interpret(self.observe(), self.tolerances)

    def settle(self) -> int:
        """Step until free cubes are at rest; returns the steps taken."""
        return settle(self.scene, self.panda)

    def is_settled(self) -> bool:
        """Whether every free cube is at rest now."""
        return settled(self.scene, self.panda)

    def reached(self, perceived: Perceived, goal: ArmState | GoalTest) -> bool:
        """The success predicate of every physical episode: the task's, on what was perceived, once settled.

        The perceived state (never the plan) is the goal (:meth:`csql_sim.core.model.task.Task.is_success`)
        or, for a partial goal (``goal`` a :class:`GoalTest`), satisfies it; and every free cube
        must be at rest.
        """
        met = Task.is_success(perceived.state, goal) if isinstance(goal, ArmState) else goal.satisfied(perceived.state)
        return met and self.is_settled()

    def execute(self, action: Action, carry_hook: CarryHook | None = None, attempt: int = 0,
                guarded: bool = False) -> Status:
        """Run the primitive of ``action`` on the current observation (``attempt``: earlier failures).

        ``guarded``: refuse without moving when the observation shows the action cannot
        start (:mod:`csql_sim.sim.control.guards`); discovery attempts illegal actions this way.
        """
        primitive = primitive_for(action, attempt=attempt)
        if guarded:
            primitive = Guarded(primitive, action, self.tolerances, self.observe)
        return primitive(self.scene, self.panda, self.observe(), self.rng, carry_hook)

    @property
    def tolerances(self) -> Tolerances:
        """The perception tolerances of the configured mode."""
        return CAMERA_TOLERANCES if self.perception == "camera" else TOLERANCES

    def recover(self, perceived: Perceived, blocked_pick: int | None = None) -> tuple[str, Status] | None:
        """Run a recovery primitive: (its name, status), or None if none applies.

        Args:
            perceived: the last perception (a cube resting flat nowhere gets ``Flatten``).
            blocked_pick: a cube whose picks keep colliding with its neighbours (gets ``Drag``).
        """
        primitive = recovery_for(perceived) if blocked_pick is None else Drag(blocked_pick)
        if primitive is None:
            return None
        status = primitive(self.scene, self.panda, self.observe(), self.rng)
        return f"{primitive.name}({letter(primitive.block)})", status

    def final_poses(self) -> tuple[Pose, ...]:
        """Every cube's pose now."""
        return tuple(self.scene.block_pose(i) for i in range(self.n))

    def add_step_hook(self, hook: Callable[[Scene], None]) -> None:
        """Call ``hook`` after every simulation step."""
        self.scene.add_step_hook(hook)
