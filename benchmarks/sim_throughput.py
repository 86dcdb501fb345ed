"""Benchmark of the physical layer: physics, executor and video throughput.

Regenerates docs/results/arm.md, the physics, executor and video throughput.

Prints raw stepSimulation steps/s against executor steps/s (target ratio >= 0.8), and,
for each renderer (the TinyRenderer, and the EGL plugin where it loads), raw
getCameraImage frames/s in one process and video frames/s through the pipeline (render,
caption, encode; all workers) against raw frames/s times workers (target >= 0.8).
Usage: python benchmarks/sim_throughput.py [--workers W] [--episodes K] [--video-only]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

import numpy as np

from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import all_states
from csql_sim.sim.control.executor import run_physical_episode
from csql_sim.sim.control.physical import PhysicalWorld
from csql_sim.sim.perception.camera import RENDER_CAMERA, capture
from csql_sim.sim.video.recording import Recording
from csql_sim.sim.video.renderer import close_quietly, egl_available
from csql_sim.sim.video.replay import apply_snapshot, replay_scene
from csql_sim.sim.video.writing import write_video


def raw_steps_per_second(steps: int, config: str) -> float:
    """Bare stepSimulation calls on a built scene (``+X``: the arm holds X in its fingers)."""
    with PhysicalWorld(3) as world:
        world.build(parse_config(config))
        t = time.perf_counter()
        world.scene.step(steps)
        return steps / (time.perf_counter() - t)


def executor_steps_per_second(episodes: int) -> tuple[float, float, float, float, float]:
    """Closed-loop steps/s, mean sim s/action, loop and setup wall, seconds inside stepSimulation."""
    states = all_states(3)
    pairs = [(s, g) for s in states for g in states if s != g]
    rng = np.random.default_rng(0)
    total_steps = 0
    loop = setup = 0.0
    per_action = []
    stepping = 0.0
    for k in rng.choice(len(pairs), size=episodes, replace=False):
        start, goal = pairs[k]
        r = run_physical_episode(start, goal, seed=int(k))
        loop += r.wall_seconds["loop"]
        setup += r.wall_seconds["setup"]
        stepping += r.wall_seconds["stepping"]
        total_steps += r.loop_steps
        per_action.append(r.sim_seconds_per_action)
    return total_steps / loop, float(np.mean(per_action)), loop, setup, stepping


def raw_frames_per_second(recording: Recording, width: int, height: int, renderer: str) -> float:
    """Bare getCameraImage calls, one process, on every 4th recorded frame (same content as the video)."""
    frames = recording.frames[::4]
    scene = replay_scene(recording.n, recording.config, renderer)
    try:
        t = time.perf_counter()
        for frame in frames:
            apply_snapshot(scene, frame.poses, frame.joints)
            capture(scene, RENDER_CAMERA, width, height)
        return len(frames) / (time.perf_counter() - t)
    finally:
        close_quietly(scene)


def video_frames_per_second(recording: Recording, width: int, height: int, workers: int, renderer: str) -> float:
    """Frames/s of write_video: render in ``workers`` processes, caption, encode an .mp4."""
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        write_video(recording, os.path.join(tmp, "bench.mp4"), width, height, workers=workers, progress=False,
                    renderer=renderer)
        return len(recording.frames) / (time.perf_counter() - t)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--video-only", action="store_true", help="only the renderers' figures")
    args = parser.parse_args()
    if not args.video_only:
        physics(args)
    video(args)


def physics(args: argparse.Namespace) -> None:
    """Raw stepping against the closed-loop executor."""
    raw_idle = raw_steps_per_second(20000, "CBA")
    raw_grip = raw_steps_per_second(20000, "AB+C")
    execd, spa, loop, setup, stepping = executor_steps_per_second(args.episodes)
    print(f"raw stepSimulation, idle:  {raw_idle:10.0f} steps/s (tower CBA, hand empty)")
    print(f"raw stepSimulation, grip:  {raw_grip:10.0f} steps/s (C held in the fingers: the contact load of a carry)")
    print(f"executor (closed loop):    {execd:10.0f} steps/s  ratio {execd / raw_idle:.2f} of idle, "
          f"{execd / raw_grip:.2f} of grip (target >= 0.8)")
    print(f"                           [{args.episodes} episodes: loop {loop:.1f} s wall; "
          f"scene setup, not counted, {setup:.1f} s]")
    print(f"                           inside Scene.step: {stepping / loop:.2f} of the loop's wall time "
          "(the rest is IK, guards, perception, policy)")
    print(f"simulated time per action: {spa:10.3f} s (target <= 1 s)")



def video(args: argparse.Namespace) -> None:
    """Raw and pipeline frames/s for each renderer that loads here (pipelines first: no EGL before a fork)."""
    r = run_physical_episode(parse_config("CBA"), parse_config("BAC"), seed=0, record=True)
    assert r.recording is not None
    renderers = ["tiny", "egl"] if egl_available() else ["tiny"]
    video_fps = {k: video_frames_per_second(r.recording, args.width, args.height, args.workers, k) for k in renderers}
    for renderer in renderers:
        raw_fps = raw_frames_per_second(r.recording, args.width, args.height, renderer)
        print(f"{renderer:<4} raw getCameraImage:    {raw_fps:9.1f} frames/s at {args.width}x{args.height} "
              "(one process, the test task's recorded frames)")
        print(f"{renderer:<4} video (render+encode): {video_fps[renderer]:9.1f} frames/s with {args.workers} "
              f"workers  ratio {video_fps[renderer] / (raw_fps * args.workers):.2f} (target >= 0.8)")
    if "egl" not in renderers:
        print("egl: pybullet's eglRenderer plugin does not load here; not measured")


if __name__ == "__main__":
    main()
