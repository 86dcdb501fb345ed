"""Recording poses during simulation, at frame times in simulated seconds."""

from __future__ import annotations

from dataclasses import dataclass, field

from csql_sim.sim.video.replay import take_snapshot
from csql_sim.sim.world.config import DEFAULT_CONFIG, SimConfig
from csql_sim.sim.world.scene import Pose, Scene


@dataclass(frozen=True)
class Caption:
    """What a frame's caption says: ``step k/K  <what>  <message>`` (K is known when rendering).

    Attributes:
        step: actions begun so far (0 before the first).
        what: the action under way, or the start/goal or outcome around it.
        message: the state message posted (with the action slot set during an action).
    """

    step: int = 0
    what: str = ""
    message: str = ""

    def text(self, total: int) -> str:
        """The caption line for an episode of ``total`` actions."""
        return f"step {self.step}/{total}  {self.what}  {self.message}".rstrip()


@dataclass(frozen=True)
class Frame:
    """One recorded instant: cube poses, Panda joint positions and the caption."""

    poses: tuple[Pose, ...]
    joints: tuple[float, ...]
    caption: Caption


@dataclass
class Recording:
    """Frames of one episode at ``fps`` frames per simulated second.

    ``names``: the cubes' names in the video's legend (PDDL object names; None: the letters).
    """

    n: int
    fps: int
    config: SimConfig = DEFAULT_CONFIG
    frames: list[Frame] = field(default_factory=list)
    names: tuple[str, ...] | None = None

    @property
    def actions(self) -> int:
        """The number of actions the recorded episode began (K of the captions)."""
        return max((f.caption.step for f in self.frames), default=0)


class Recorder:
    """A scene step hook that snapshots the scene every 1/fps simulated seconds."""

    def __init__(self, scene: Scene, fps: int, caption: Caption | None = None) -> None:
        self.scene = scene
        self.recording = Recording(n=scene.n, fps=fps, config=scene.config)
        self.every = max(1, round(1.0 / (fps * scene.config.physics.time_step)))
        self.caption = caption or Caption()
        self._capture()

    def _capture(self) -> None:
        snap = take_snapshot(self.scene)
        self.recording.frames.append(Frame(poses=snap.poses, joints=snap.joints, caption=self.caption))

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
