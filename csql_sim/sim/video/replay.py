"""Pose replay: snapshots of a running scene, and replay scenes posed from them.

During an episode a :class:`~csql_sim.sim.video.recording.Recorder` takes a :class:`Snapshot`
(every cube's pose, every Panda joint) at frame times; for rendering, a replay-only
:class:`~csql_sim.sim.world.scene.Scene` (never stepped) is set to each snapshot in turn.
"""

from __future__ import annotations

from dataclasses import dataclass

from csql_sim.sim.video.renderer import RendererError, egl_scene
from csql_sim.sim.world.config import SimConfig
from csql_sim.sim.world.scene import Pose, Scene

PANDA_JOINTS = range(11)  # seven arm joints, two fixed hand joints, two fingers


@dataclass(frozen=True)
class Snapshot:
    """Every cube's pose and every Panda joint position at one instant."""

    poses: tuple[Pose, ...]
    joints: tuple[float, ...]


def take_snapshot(scene: Scene) -> Snapshot:
    """The scene's cube poses and Panda joint positions now."""
    return Snapshot(poses=tuple(scene.block_pose(i) for i in range(scene.n)),
                    joints=tuple(scene.joint_positions(scene.bodies["panda"], PANDA_JOINTS)))


def replay_scene(n: int, config: SimConfig | None = None, renderer: str = "tiny") -> Scene:
    """A scene for replay only: the bodies are posed from snapshots and never stepped.

    ``renderer`` (``"tiny"`` or ``"egl"``, see :mod:`csql_sim.sim.video.renderer`) draws its images.
    """
    if renderer != "egl":
        return Scene(n, config, physics=False)
    scene = egl_scene(n, config)
    if scene is None:
        raise RendererError("--renderer egl: pybullet's eglRenderer plugin did not load in a render worker")
    return scene


def apply_snapshot(scene: Scene, poses: tuple[Pose, ...], joints: tuple[float, ...]) -> None:
    """Pose a replay scene's cubes and Panda joints (never a physics scene during an episode).

    Raises:
        RuntimeError: if ``scene`` is a physics scene.
    """
    if not scene.replay_only:
        raise RuntimeError("apply_snapshot is for replay scenes only")
    for i, pose in enumerate(poses):
        scene.set_block_pose(i, pose.position, pose.orientation)
    panda = scene.bodies["panda"]
    for j, q in enumerate(joints):
        scene.reset_joint(panda, j, q)


__all__ = ["Snapshot", "apply_snapshot", "replay_scene", "take_snapshot"]
