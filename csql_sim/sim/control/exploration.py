"""The simulated arm as an explorable world for rule discovery (:mod:`csql_sim.discovery.world`'s protocol).

Each attempt runs the action's real primitive behind its guard
(:mod:`csql_sim.sim.control.guards`): an action whose preconditions do not hold is refused
before the arm moves, by what the observation shows. ``perturb`` jitters every start scene
and, after some attempts, nudges a clear cube with an external force (it may push a tower
top off), the noise the induction must cope with. When perception cannot name a state (a
cube tilted or fallen off), the episode ends and a new scene is built from a random
hand-empty state drawn from the run's generator (counted as a restart).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from csql_sim.core.state.world import Action, State, all_states
from csql_sim.discovery.world import Attempt
from csql_sim.sim.control.perturbation import PERTURBATION, Perturbation, nudge
from csql_sim.sim.control.physical import PhysicalWorld, SimError
from csql_sim.sim.video.recording import Caption, Recorder
from csql_sim.sim.world.config import DEFAULT_CONFIG, SimConfig

CAPTION_HOLD = 0.6  # simulated seconds the verdict of an attempt stays on screen in a video


@dataclass
class ArmWorld:
    """The Panda and its cubes behind the :class:`~csql_sim.discovery.world.ExplorableWorld` protocol.

    Args:
        n: number of cubes.
        rng: the run's one generator (start scenes, perturbations, putdown spots).
        perception: ``"pose"`` or ``"camera"``.
        perturb: jitter start scenes and nudge cubes now and then.
        nudge_probability: chance of a nudge after an attempt under ``perturb``.
        recorder_fps: when set, record frames (one scene only: no restarts are recorded).
        config: scene settings.
        perturbation: force and duration of a nudge.
    """

    n: int
    rng: np.random.Generator
    perception: str = "pose"
    perturb: bool = False
    nudge_probability: float = 0.05
    recorder_fps: int | None = None
    config: SimConfig = DEFAULT_CONFIG
    perturbation: Perturbation = PERTURBATION
    world: PhysicalWorld | None = field(init=False, default=None)
    recorder: Recorder | None = field(init=False, default=None)
    attempts: int = field(init=False, default=0)

    def __post_init__(self) -> None:
        self.restart()

    def restart(self) -> None:  # noqa: D102
        if self.recorder is not None and self.world is not None:
            raise SimError("perception failed during a recorded discovery episode; try another seed")
        self.close()
        resting = [s for s in all_states(self.n) if s.held is None]
        start = resting[int(self.rng.integers(len(resting)))]
        seed = int(self.rng.integers(2**31))
        self.world = PhysicalWorld(self.n, seed, self.perception, self.config)
        self.world.rng = self.rng  # one generator for the whole run
        self.world.build(start, jitter=self.perturb and self.perturbation.jitter_start)
        if self.recorder_fps is not None:
            self.recorder = Recorder(self.world.scene, self.recorder_fps)
            self.world.add_step_hook(self.recorder)

    def perceive(self) -> State | None:  # noqa: D102
        return self.world.perceive().state

    def attempt(self, action: Action) -> Attempt:  # noqa: D102
        scene = self.world.scene
        start = scene.steps
        self.attempts += 1
        if self.recorder is not None:
            self.recorder.caption = Caption(step=self.attempts, what=action.name())
        status = self.world.execute(action, guarded=True)
        if self.recorder is not None:
            verdict = "done" if status.ok else f"FAILED ({status.reason})"
            self.recorder.caption = Caption(step=self.attempts, what=f"{action.name()} {verdict}")
            self.recorder.still(round(self.recorder.recording.fps * CAPTION_HOLD))
        events: tuple[str, ...] = ()
        if self.perturb and self.rng.random() < self.nudge_probability:
            events = (nudge(self.world, self.rng, self.perturbation),)
        return Attempt(status.ok, status.reason, (scene.steps - start) * self.config.physics.time_step, events,
                       status.refused)  # only a precondition refusal, never "did not move"

    def close(self) -> None:
        """Release the physics client."""
        if self.world is not None:
            self.world.close()
            self.world = None

    def __enter__(self) -> ArmWorld:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
