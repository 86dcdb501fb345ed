"""What a video costs: ``execute`` with ``--out V`` against the same command without, in one run.

Regenerates docs/video.md, the table of what a video costs.

    python benchmarks/video_speed.py [--repeats 3] [--workers K] [--renderer auto]

Two tasks, each run by the command line (a fresh process each time, as a user runs it):

* the 10-cube task ``benchmarks/ten_cubes.pddl`` (24 actions by GN1): ``csql-sim execute
  --problem benchmarks/ten_cubes.pddl --planner gn1`` with and without ``--out ten.mp4``;
* the 3-block demo task (CBA -> BAC, the paper's test task; BFS) with and without ``--out three.mp4``.

The video is the default one: 640x480, 24 frames per second of video, ``--speed 2`` (twice
real time), the top view inset, the cubes named. Each command runs ``--repeats`` times, the
two variants in turn; the ratio is min(with video) / min(without), the minimum because the
machine may be shared (other work only ever adds time). Prints the date, the cores, the
load average before the runs and every time measured.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path

HERE = Path(__file__).resolve().parent
TEN = HERE / "ten_cubes.pddl"
THREE = """; the paper's test task: CBA (A on B on C) -> BAC (C on A on B)
(define (problem test-task) (:domain blocks) (:objects a b c)
  (:init (handempty) (ontable c) (on b c) (on a b) (clear a))
  (:goal (and (ontable b) (on a b) (on c a))))
"""


def timed(cmd: list[str]) -> float:
    """Wall seconds of one run of ``cmd`` (which must succeed)."""
    t0 = time.perf_counter()
    done = subprocess.run(cmd, capture_output=True, text=True, check=False)
    seconds = time.perf_counter() - t0
    if done.returncode != 0:
        sys.exit(f"video_speed: {' '.join(cmd)} failed ({done.returncode}): {done.stderr.strip()[-400:]}")
    return seconds


def measure(name: str, base: list[str], video: Path, repeats: int, extra: list[str]) -> dict:
    """Min wall seconds of ``base`` without and with ``--out video`` (alternating), and their ratio."""
    plain, with_video = [], []
    for _ in range(repeats):
        plain.append(timed(base))
        video.unlink(missing_ok=True)
        Path(f"{video}.json").unlink(missing_ok=True)
        with_video.append(timed([*base, "--out", str(video), *extra]))
    size = video.stat().st_size
    ratio = min(with_video) / min(plain)
    print(f"{name}: without video {min(plain):.1f} s, with video {min(with_video):.1f} s -> {ratio:.2f}x "
          f"(video {size / 1e6:.2f} MB; runs without: {', '.join(f'{t:.1f}' for t in plain)} s; "
          f"with: {', '.join(f'{t:.1f}' for t in with_video)} s)")
    return {"plain": plain, "video": with_video, "ratio": ratio}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="runs of each command (default 3; the min counts)")
    parser.add_argument("--workers", type=int, default=None, help="rendering processes (default: the cores)")
    parser.add_argument("--renderer", default="auto", help="video renderer (default auto)")
    args = parser.parse_args()
    extra = ["--renderer", args.renderer] + ([] if args.workers is None else ["--workers", str(args.workers)])
    cli = [sys.executable, "-m", "csql_sim"]
    now = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    print(f"video_speed {now}: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} before the runs; "
          f"640x480, 24 fps, speed 2, top view; min of {args.repeats} runs each")
    with tempfile.TemporaryDirectory() as tmp:
        three = Path(tmp) / "three.pddl"
        three.write_text(THREE)
        ten = measure("10 cubes, 24 actions (gn1)", [*cli, "execute", "--problem", str(TEN), "--planner", "gn1",
                                                     "--quiet"], Path(tmp) / "ten.mp4", args.repeats, extra)
        small = measure("3 blocks, CBA -> BAC (bfs)", [*cli, "execute", "--problem", str(three), "--planner", "bfs",
                                                      "--quiet"], Path(tmp) / "three.mp4", args.repeats, extra)
    print(f"targets: 10 cubes <= 2x ({'met' if ten['ratio'] <= 2 else 'NOT met'}), "
          f"3 blocks <= 1.5x ({'met' if small['ratio'] <= 1.5 else 'NOT met'}); "
          f"load average after {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
