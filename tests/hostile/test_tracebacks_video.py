"""Videos on a full disk (issue 27, class 3): one error line, not the encoder's messages or tracebacks.

ffmpeg's own messages reached our stderr (8 lines for an .mp4), and imageio's GIF writer
failed again in its finalizers ("Exception ignored" tracebacks, 47 lines for a .gif). The
writers now capture ffmpeg's messages and encode GIFs into a file they close themselves.
"""

from __future__ import annotations

from hostile_cli import csql
from video_cases import only_fixtures_left, put_fixtures

SMALL = ("--width", 160, "--height", 120, "--fps", 10, "--workers", 1)  # about 95 KB: more than the 64 KiB disk


def test_z_render_mp4_full_disk(tiny_fs):
    run = csql(tiny_fs, "render", "--quiet", "--start", "CBA", "--goal", "BAC", "--out", "v.mp4", *SMALL)
    run.refused("v.mp4")
    assert run.stdout == ""
    only_fixtures_left(tiny_fs, {})


def test_z_render_gif_full_disk(tiny_fs):
    run = csql(tiny_fs, "render", "--quiet", "--start", "CBA", "--goal", "BAC", "--out", "v.gif", *SMALL)
    run.refused("v.gif")
    assert run.stdout == ""
    only_fixtures_left(tiny_fs, {})


def test_z_execute_gif_full_disk(tiny_fs):
    fixtures = put_fixtures(tiny_fs)
    run = csql(tiny_fs, "execute", "--quiet", "--problem", "ok3.pddl", "--plan", "good.plan", "--out", "v.gif")
    run.refused("v.gif")
    assert run.stdout == ""
    only_fixtures_left(tiny_fs, fixtures)
