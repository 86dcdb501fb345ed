"""A video is read back before it replaces anything; rendering starts no more workers than cores.

Under ``ulimit -f`` ffmpeg was killed half way, ``render`` printed "wrote v.mp4" and exited 0,
and the cut file had replaced a valid video. ``--workers 1000`` started a process per chunk
of frames until the kernel's OOM killer fired.
"""

import os
import resource
import subprocess
import sys

import pytest

from csql_sim.core.state.notation import parse_config
from csql_sim.infra.errors import CsqlError
from csql_sim.sim.control.executor import run_physical_episode
from csql_sim.sim.video import writing as video
from csql_sim.sim.video.writing import VideoError, video_frame_count, write_video

HANG_GUARD = 120.0  # seconds; only against a hang, never the assertion


@pytest.fixture(scope="module")
def recording():
    r = run_physical_episode(parse_config("A,B"), parse_config("AB"), seed=0, record=True, fps=5)
    return r.recording


def _cut_after_close(monkeypatch, keep: int) -> None:
    """Make every video writer leave only the first ``keep`` bytes, as an encoder killed half way does."""
    real = video._open_writer

    class Cut:
        def __init__(self, path, fps, suffix):
            self.path, self.writer = path, real(path, fps, suffix)

        def __enter__(self):
            return self.writer.__enter__()

        def __exit__(self, *exc):
            self.writer.__exit__(*exc)
            os.truncate(self.path, keep)

    monkeypatch.setattr(video, "_open_writer", Cut)


@pytest.mark.parametrize("name", ["v.mp4", "v.gif"])
def test_a_cut_video_fails_and_keeps_the_old_one(recording, tmp_path, monkeypatch, name):
    out = tmp_path / name
    out.write_bytes(b"the old, valid video")
    _cut_after_close(monkeypatch, keep=600)
    with pytest.raises(VideoError) as caught:
        write_video(recording, out, 32, 24, workers=1, progress=False)
    assert len(str(caught.value).splitlines()) == 1 and name in str(caught.value)
    assert out.read_bytes() == b"the old, valid video"
    assert [p.name for p in tmp_path.iterdir()] == [name]  # no temporary file left


@pytest.mark.parametrize("name", ["v.mp4", "v.gif"])
def test_a_whole_video_reads_back(recording, tmp_path, name):
    out = write_video(recording, tmp_path / name, 32, 24, workers=1, progress=False)
    video.verify_video(out, out.suffix, video_frame_count(recording))
    with pytest.raises(VideoError):  # more frames given than the file holds
        video.verify_video(out, out.suffix, 0 if name.endswith(".gif") else video_frame_count(recording) + 1)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_FSIZE semantics")
def test_render_under_a_file_size_limit_fails_with_one_line_and_keeps_the_old_video(tmp_path):
    argv = [sys.executable, "-m", "csql_sim", "render", "--start", "AB", "--goal", "BA", "--out", "v.mp4",
            "--width", "64", "--height", "48", "--fps", "5", "--workers", "1", "--quiet"]
    first = subprocess.run(argv, cwd=tmp_path, capture_output=True, timeout=HANG_GUARD)
    assert first.returncode == 0, first.stderr
    old = {p.name: p.read_bytes() for p in tmp_path.iterdir()}  # the video and its sidecar
    size = len(old["v.mp4"])

    def limit():  # the same video again, cut just short of its end: ffmpeg dies once every frame is sent
        resource.setrlimit(resource.RLIMIT_FSIZE, (size - 64, size - 64))

    proc = subprocess.run(argv, cwd=tmp_path, preexec_fn=limit, capture_output=True, text=True, timeout=HANG_GUARD)
    assert proc.returncode != 0 and "wrote" not in proc.stdout
    assert len(proc.stderr.splitlines()) == 1 and "v.mp4" in proc.stderr
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == old  # nothing replaced, no temporary file


def test_rendering_workers_are_capped_at_the_cores_and_chunks(recording, tmp_path, monkeypatch):
    started, real = [], video._map_chunks

    def spy(rec, chunks, view, workers, renderer):
        started.append((len(chunks), workers))
        return real(rec, chunks, view, 1, renderer)

    monkeypatch.setattr("os.cpu_count", lambda: 2)
    monkeypatch.setattr(video, "_map_chunks", spy)
    write_video(recording, tmp_path / "v.gif", 32, 24, workers=1000, progress=False)
    assert len(started) == 1 and started[0][0] > 2 and started[0][1] == 2
    write_video(recording, tmp_path / "v.gif", 32, 24, workers=None, progress=False, renderer="tiny")
    assert started[1][1] == 2
    # the flat painter starts a process per FRAMES_PER_WORKER frames: a short recording is painted here
    assert len(recording.frames) < video.FRAMES_PER_WORKER
    write_video(recording, tmp_path / "v.gif", 32, 24, workers=None, progress=False, renderer="flat")
    assert started[2][1] == 1


def test_bad_options_still_fail_before_rendering(recording, tmp_path):
    with pytest.raises(CsqlError):
        write_video(recording, tmp_path / "v.avi", 32, 24, workers=1, progress=False)
