"""The picture of ten cubes stacked by the simulated Panda: ``docs/ten_tower.png``.

Regenerates docs/sim.md and docs/results/arm.md, the picture docs/ten_tower.png.

The tower is built physically, by a closed-loop episode (perceive, ask the policy, run the
pick or place primitive, perceive again; cubes move only through contact), never by
placing the cubes. The picture is the episode's final frame, rendered off-screen from the
recorded poses, with a caption saying what was run and what perception saw at the end.

    python benchmarks/sim_ten_tower.py                       # GN1, camera perception, docs/ten_tower.png
    python benchmarks/sim_ten_tower.py --rules lifted.json   # the learned lifted rules instead

Bad input is one line on stderr and exit status 2; the output is checked writable before
the episode runs and written atomically. Exit status 1 if the tower was not reached.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np
from PIL import Image

from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.state.notation import parse_config
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import atomic_output, check_output_file
from csql_sim.sim.control.executor import EpisodeResult, run_physical_episode
from csql_sim.sim.perception.camera import Camera, capture
from csql_sim.sim.video.replay import apply_snapshot, replay_scene
from csql_sim.sim.video.writing import caption_image
from csql_sim.sim.world.arm_state import check_arm_blocks, check_arm_policy

START = "A,B,C,D,E,F,G,H,I,J"  # ten cubes side by side on the arc, F in the middle
GOAL = "FGHIJABCDE"  # one tower on F: G on F, ..., E on top
TOWER_CAMERA = Camera(eye=(1.45, -0.35, 0.75), target=(0.35, 0.0, 0.28), fov=45.0, width=800, height=600)
"""Front left of the table, looking at the middle of the arc and up to the raised hand."""


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--start", default=START, help=f"start configuration (default {START})")
    p.add_argument("--goal", default=GOAL, help=f"goal configuration (default {GOAL})")
    p.add_argument("--rules", help="lifted rules (load_policy) instead of the GN1 baseline")
    p.add_argument("--perception", choices=("pose", "camera"), default="camera", help="default camera")
    p.add_argument("--seed", type=int, default=0, help="episode seed (default 0)")
    p.add_argument("--out", default="docs/ten_tower.png", help="the PNG to write (default docs/ten_tower.png)")
    p.add_argument("--width", type=int, default=800)
    p.add_argument("--height", type=int, default=600)
    return p.parse_args(argv)


def caption(result: EpisodeResult, policy: str, perception: str, seconds: float) -> str:
    """The caption line: the task, the policy, the outcome as perceived."""
    verdict = "goal perceived" if result.success else f"NOT reached ({result.reason})"
    return (f"{len(result.final_poses)} cubes, {result.start} -> {result.goal}, {policy}: {result.length} actions "
            f"(optimal {result.optimal_length}), {perception} perception, {verdict}; {result.sim_seconds:.0f} s "
            f"simulated, {seconds:.0f} s wall")


def render_final(result: EpisodeResult, text: str, width: int, height: int) -> np.ndarray:
    """The recording's last frame from :data:`TOWER_CAMERA`, captioned, with the cubes' legend."""
    recording = result.recording
    assert recording is not None
    frame = recording.frames[-1]
    scene = replay_scene(recording.n, recording.config)
    try:
        apply_snapshot(scene, frame.poses, frame.joints)
        rgb, _, _ = capture(scene, TOWER_CAMERA, width, height)
    finally:
        scene.close()
    return caption_image(rgb, text, legend=recording.n)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        start, goal = parse_config(args.start), parse_config(args.goal)
        check_arm_blocks(start.n)
        policy = Gn1Policy() if args.rules is None else load_policy(args.rules, start.n)
        check_arm_policy(policy, start.n)
        out = check_output_file(args.out, "picture")
        if out.suffix.lower() != ".png":
            raise CsqlError(f"--out must name a .png file, got {args.out!r}")
        t0 = time.perf_counter()
        result = run_physical_episode(start, goal, policy, seed=args.seed, record=True, fps=10,
                                      perception=args.perception)
        seconds = time.perf_counter() - t0
        name = "GN1 baseline" if args.rules is None else f"lifted rules {args.rules}"
        image = render_final(result, caption(result, name, args.perception, seconds), args.width, args.height)
        with atomic_output(out) as tmp:
            Image.fromarray(image).save(tmp, format="PNG")
    except CsqlError as exc:
        print(f"render_tower: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    print(f"{caption(result, name, args.perception, seconds)}\nwrote {out}")
    return 0 if result.success else 1


if __name__ == "__main__":
    sys.exit(main())
