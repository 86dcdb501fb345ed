"""Hangs of the video writer (issue 27, class 2): ``execute --video`` on a full disk never exited.

A thread was left writing frames into ffmpeg's pipe: imageio's writer blocks for ever on an
ffmpeg that has stopped reading without exiting. The writer now sends frames with a
deadline and kills and reaps ffmpeg on any failure: one line naming the file, exit 2.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

from hostile_cli import csql, environment
from video_cases import only_fixtures_left, put_fixtures


def test_ex_video_tiny_fs(tiny_fs):
    fixtures = put_fixtures(tiny_fs)
    run = csql(tiny_fs, "execute", "--quiet", "--problem", "ok3.pddl", "--plan", "good.plan", "--out", "v.mp4",
               timeout=240)
    run.refused("v.mp4")
    assert run.stdout == ""
    only_fixtures_left(tiny_fs, fixtures)


STUCK_ENCODER = """#!/bin/sh
echo $$ > "{pidfile}"
exec sleep 300
"""

WRITE_WITH_A_STUCK_ENCODER = """
import sys
from csql_sim.core.state.notation import parse_config
from csql_sim.sim.video import encoders as video_writers
from csql_sim.sim.video import writing as video
from csql_sim.sim.control.executor import run_physical_episode

video_writers.STALL_SECONDS = 1.0
recording = run_physical_episode(parse_config("A,B"), parse_config("AB"), seed=0, record=True, fps=5).recording
try:
    video.write_video(recording, "v.mp4", 160, 120, workers=1, progress=False, renderer="tiny")
except video.VideoError as exc:
    print("csql-sim: error:", exc, file=sys.stderr)
    sys.exit(2)
"""


def test_ex_video_tiny_fs_stuck_encoder_is_killed(work):
    """The root of the hang: an encoder that neither reads nor exits fails the write after the stall time."""
    pidfile = work / "ffmpeg.pid"
    fake = work / "ffmpeg"
    fake.write_text(STUCK_ENCODER.format(pidfile=pidfile))
    fake.chmod(0o755)
    env = {**environment(work), "IMAGEIO_FFMPEG_EXE": str(fake)}
    began = time.monotonic()
    done = subprocess.run([sys.executable, "-c", WRITE_WITH_A_STUCK_ENCODER], cwd=work, env=env,
                          stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and "v.mp4" in done.stderr and "Traceback" not in done.stderr, done.stderr
    assert time.monotonic() - began < 90
    pid = int(pidfile.read_text())
    assert not Path(f"/proc/{pid}").exists()  # killed, not left sleeping
    assert sorted(os.listdir(work)) == ["ffmpeg", "ffmpeg.pid"]  # no temporary video left
