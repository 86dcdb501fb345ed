"""The render job: one recorded episode on the arm, its captioned video and provenance sidecar."""

from __future__ import annotations

import json
import os
from pathlib import Path

from csql_sim.core.policies.policy import Policy
from csql_sim.infra.files import write_or_keep
from csql_sim.infra.provenance import provenance
from csql_sim.sim.control import EpisodeResult, run_physical_episode
from csql_sim.sim.perception import NO_NOISE, CameraNoise
from csql_sim.sim.video import VideoOptions, resolve_renderer, video_frame_count, write_video
from csql_sim.sim.world import ArmState, cube_legend

SIDECAR_FORMAT = "csql-sim video provenance"
SIDECAR_VERSION = 1


def render_episode(start: ArmState, goal: ArmState, out: str | os.PathLike, policy: Policy | None = None,
                   seed: int = 0, width: int = 640, height: int = 480, fps: int = 24,
                   workers: int | None = None, perturb: bool = False, perception: str = "pose",
                   progress: bool = True, provenance_extra: dict | None = None,
                   camera_noise: CameraNoise = NO_NOISE, renderer: str = "auto",
                   names: tuple[str, ...] | None = None, speed: float = 2.0) -> tuple[EpisodeResult, Path]:
    """Run one recorded episode, write its video and the video's provenance sidecar (``<video>.json``).

    The sidecar (:func:`sidecar_record`) is written after the video; a failed write of it is
    a one-line OutputError (its text kept in the temporary folder).

    Args:
        start: the start configuration: a State (2..30 cubes).
        goal: the goal configuration.
        out: the .mp4 or .gif to write.
        policy: any Policy; the BFS planner when None (n <= 6; past six a lifted policy).
        seed: the episode's seed.
        width: frame width in pixels.
        height: frame height in pixels.
        fps: frames per second of video.
        workers: rendering processes (default: the cores, capped by the frames).
        perturb: jitter the start, nudge a cube, drop a carried cube.
        perception: ``"pose"`` or ``"camera"``.
        progress: show progress bars on stderr.
        provenance_extra: further parameters to record in the sidecar (e.g. the rule file).
        camera_noise: sensor noise of camera perception.
        renderer: ``"flat"``, ``"tiny"``, ``"egl"`` or ``"auto"`` (EGL on a GPU, else flat).
        names: the cubes' names written on them (default: their letters); the sidecar's
            ``video.legend`` maps each to its colour.
        speed: simulated seconds per second of video (a time-lapse past 1).

    Returns:
        The episode result and the path of the video (written even if the episode failed).
    """
    options = VideoOptions(width, height, fps, speed, renderer, workers)
    options.check(out)
    renderer = resolve_renderer(renderer)  # an unusable --renderer fails before the episode runs
    from tqdm import tqdm

    from csql_sim.sim.world import arm_optimal_length

    with tqdm(total=arm_optimal_length(start, goal), desc="executing", unit="action", disable=not progress, delay=1.0,
              leave=False) as bar:
        result = run_physical_episode(start, goal, policy, seed=seed, record=True, perturb=perturb,
                                      perception=perception, fps=options.sample_rate, on_action=lambda _k: bar.update(),
                                      camera_noise=camera_noise)
    assert result.recording is not None
    result.recording.names = names
    path = write_video(result.recording, out, width, height, fps, workers, progress=progress, renderer=renderer)
    record = provenance(start=start.notation(), goal=goal.notation(), policy=getattr(policy, "name", "bfs"),
                        seed=seed, width=width, height=height, fps=fps, speed=speed, perturb=perturb,
                        perception=perception,
                        camera_noise=[camera_noise.depth, camera_noise.colour],
                        renderer=renderer,
                        **(provenance_extra or {}))
    video = {"file": path.name, "frames": video_frame_count(result.recording, fps),
             "actions": result.length, "success": result.success, "reason": result.reason,
             "legend": cube_legend(start.n, names)}
    write_or_keep([(sidecar_path(path), json.dumps(sidecar_record(record, video), indent=1) + "\n")])
    return result, path


def sidecar_record(record: dict, video: dict) -> dict:
    """The sidecar's JSON: ``format`` and ``version`` (of the sidecar) first, then the provenance record.

    The provenance record's own ``version`` (the package's) is ``package_version`` here::

        {"format": "csql-sim video provenance", "version": 1, "package": "csql-sim",
         "package_version": "...", "python": "...", "parameters": {...}, "video": {...}}
    """
    rest = {k: v for k, v in record.items() if k != "version"}
    return {"format": SIDECAR_FORMAT, "version": SIDECAR_VERSION, **rest,
            "package_version": record.get("version"), "video": video}


def sidecar_path(video: str | os.PathLike) -> Path:
    """The provenance sidecar of a video: ``<video>.json``."""
    video = Path(video)
    return video.with_name(video.name + ".json")
