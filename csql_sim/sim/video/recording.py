"""Recording poses during simulation, at frame times in simulated seconds."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from csql_sim.core.files.ipc_plan import ipc_action
from csql_sim.core.state.state import State
from csql_sim.core.state.world import Action
from csql_sim.sim.video.painter import ArmShape
from csql_sim.sim.video.replay import take_snapshot
from csql_sim.sim.world.arm_state import label
from csql_sim.sim.world.config import DEFAULT_CONFIG, SimConfig
from csql_sim.sim.world.scene import Pose, Scene


@dataclass(frozen=True)
class Caption:
    """What a frame's caption says: ``step k/K  <action>  <states>  <what>  <message>`` (K is known when rendering).

    The action and the states are kept as such, not as text, so that the caption names the
    blocks as the user does (:meth:`text` with the problem's names; letters without).

    Attributes:
        step: actions begun so far (0 before the first).
        what: free text: an outcome or a failure.
        message: the state message the policy saw (the one the step table prints).
        action: the action under way, if any.
        states: labelled states shown, e.g. ``(("start", s), ("goal", g))`` or ``(("perceived", s),)``.
    """

    step: int = 0
    what: str = ""
    message: str = ""
    action: Action | None = None
    states: tuple[tuple[str, State], ...] = ()

    def text(self, total: int, names: Sequence[str] | None = None) -> str:
        """The caption line for an episode of ``total`` actions, in ``names`` (None: the cube letters)."""
        parts = [f"step {self.step}/{total}"]
        if self.action is not None:
            parts.append(label(self.action) if names is None else ipc_action(self.action, names))
        parts += [f"{word} {state_text(state, names)}" for word, state in self.states]
        parts += [self.what, self.message]
        return "  ".join(p for p in parts if p)


def state_text(state: State, names: Sequence[str] | None = None) -> str:
    """A state in the notation: with the cube letters, or with ``names`` (towers bottom-up, comma-separated)."""
    return state.notation() if names is None else state.named(tuple(names)).named_notation()


@dataclass(frozen=True)
class Frame:
    """One recorded instant: cube poses, Panda joint positions and the caption."""

    poses: tuple[Pose, ...]
    joints: tuple[float, ...]
    caption: Caption
    links: tuple[Pose, ...] = ()  # the Panda links' centre-of-mass frames, as the recording's ``arm`` lists them


@dataclass
class Recording:
    """Frames of one episode at ``fps`` frames per simulated second.

    ``names``: the cubes' names in the video's legend (PDDL object names; None: the letters).
    ``arm``: the Panda's shape, whose links each frame's ``links`` pose (the flat painter's).
    """

    n: int
    fps: int
    config: SimConfig = DEFAULT_CONFIG
    frames: list[Frame] = field(default_factory=list)
    names: tuple[str, ...] | None = None
    arm: ArmShape | None = None

    @property
    def actions(self) -> int:
        """The number of actions the recorded episode began (K of the captions)."""
        return max((f.caption.step for f in self.frames), default=0)


class Recorder:
    """A scene step hook that snapshots the scene every 1/fps simulated seconds."""

    def __init__(self, scene: Scene, fps: int, caption: Caption | None = None) -> None:
        self.scene = scene
        self.arm = ArmShape.of(scene)
        self.recording = Recording(n=scene.n, fps=fps, config=scene.config, arm=self.arm)
        self.every = max(1, round(1.0 / (fps * scene.config.physics.time_step)))
        self.caption = caption or Caption()
        self._capture()

    def _capture(self) -> None:
        snap = take_snapshot(self.scene)
        self.recording.frames.append(Frame(poses=snap.poses, joints=snap.joints, caption=self.caption,
                                           links=self.arm.poses(self.scene)))

    def __call__(self, scene: Scene) -> None:
        if scene.steps % self.every == 0:
            self._capture()

    def still(self, count: int) -> None:
        """Append ``count`` frames of the scene as it is (a pause with the current caption)."""
        for _ in range(count):
            self._capture()

    def finish(self) -> Recording:
        """The recording with a final frame of the end state."""
        self._capture()
        return self.recording
