"""Physical execution on a simulated Franka Panda (the only package that imports pybullet, in sim/client.py).

Main entry points:

* :func:`run_physical_episode` - closed-loop execution of a policy from a start to a goal.
* :func:`write_video` - render a recorded episode to a captioned .mp4 or .gif.
* :func:`render_episode` - both in one call.
* :class:`PhysicalBlocksEnv` - the symbolic environment's Gymnasium interface.
* :func:`load_policy` - BFS or the greedy policy of a rule-base file.
"""

from __future__ import annotations

import os
from pathlib import Path

from csql_sim.policy import Policy, load_policy
from csql_sim.sim.env import PhysicalBlocksEnv
from csql_sim.sim.executor import EpisodeResult, Perturbation, run_physical_episode
from csql_sim.sim.physical import PhysicalWorld, SimError
from csql_sim.sim.recording import Recording
from csql_sim.sim.render import VideoError, check_video_options, write_video
from csql_sim.world import State


def render_episode(start: State, goal: State, out: str | os.PathLike, policy: Policy | None = None,
                   seed: int = 0, width: int = 640, height: int = 480, fps: int = 30,
                   workers: int | None = None, perturb: bool = False, perception: str = "pose",
                   progress: bool = True) -> tuple[EpisodeResult, Path]:
    """Run one recorded episode and write its video.

    Returns:
        The episode result and the path of the video (written even if the episode failed).
    """
    check_video_options(out, width, height, fps)
    result = run_physical_episode(start, goal, policy, seed=seed, record=True, perturb=perturb,
                                  perception=perception, fps=fps)
    assert result.recording is not None
    path = write_video(result.recording, out, width, height, fps, workers, progress=progress)
    return result, path


__all__ = [
    "EpisodeResult",
    "Perturbation",
    "PhysicalBlocksEnv",
    "PhysicalWorld",
    "Recording",
    "SimError",
    "VideoError",
    "load_policy",
    "render_episode",
    "run_physical_episode",
    "write_video",
]
