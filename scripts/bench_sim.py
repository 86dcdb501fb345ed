"""Benchmark of the physical layer: physics, executor and video throughput.

Prints raw stepSimulation steps/s against executor steps/s (target ratio >= 0.8), and
video frames/s against raw getCameraImage frames/s times workers (target >= 0.8).
Usage: python scripts/bench_sim.py [--workers W] [--episodes K]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

import numpy as np

from csql_sim.sim.camera import RENDER_CAMERA, capture
from csql_sim.sim.executor import run_episode
from csql_sim.sim.physical import PhysicalWorld
from csql_sim.sim.render import write_video
from csql_sim.world import all_states, parse_config


def raw_steps_per_second(steps: int) -> float:
    with PhysicalWorld(3) as world:
        world.build(parse_config("CBA"))
        t = time.perf_counter()
        world.scene.step(steps)
        return steps / (time.perf_counter() - t)


def executor_steps_per_second(episodes: int) -> tuple[float, float, float]:
    states = all_states(3)
    pairs = [(s, g) for s in states for g in states if s != g]
    rng = np.random.default_rng(0)
    total_steps = 0
    wall = 0.0
    per_action = []
    for k in rng.choice(len(pairs), size=episodes, replace=False):
        start, goal = pairs[k]
        t = time.perf_counter()
        r = run_episode(start, goal, seed=int(k))
        wall += time.perf_counter() - t
        total_steps += round(r.sim_seconds * 240)
        per_action.append(r.sim_seconds_per_action)
    return total_steps / wall, float(np.mean(per_action)), wall


def raw_frames_per_second(frames: int, width: int, height: int) -> float:
    with PhysicalWorld(3) as world:
        world.build(parse_config("CBA"))
        capture(world.scene, RENDER_CAMERA, width, height)
        t = time.perf_counter()
        for _ in range(frames):
            capture(world.scene, RENDER_CAMERA, width, height)
        return frames / (time.perf_counter() - t)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    args = parser.parse_args()

    raw = raw_steps_per_second(20000)
    execd, spa, wall = executor_steps_per_second(args.episodes)
    print(f"raw stepSimulation:        {raw:10.0f} steps/s")
    print(f"executor (closed loop):    {execd:10.0f} steps/s  ratio {execd / raw:.2f} (target >= 0.8)"
          f"  [{args.episodes} episodes, {wall:.1f} s wall, scene setup included]")
    print(f"simulated time per action: {spa:10.3f} s (target <= 1 s)")

    raw_fps = raw_frames_per_second(20, args.width, args.height)
    r = run_episode(parse_config("CBA"), parse_config("BAC"), seed=0, record=True)
    assert r.recording is not None
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        write_video(r.recording, os.path.join(tmp, "bench.mp4"), args.width, args.height,
                    workers=args.workers, progress=False)
        video_fps = len(r.recording.frames) / (time.perf_counter() - t)
    print(f"raw getCameraImage:        {raw_fps:10.1f} frames/s at {args.width}x{args.height} (one process)")
    print(f"video (render + encode):   {video_fps:10.1f} frames/s with {args.workers} workers  ratio "
          f"{video_fps / (raw_fps * args.workers):.2f} (target >= 0.8)")


if __name__ == "__main__":
    main()
