import imageio.v2 as imageio
import pytest

from csql_sim.errors import CsqlError
from csql_sim.notation import parse_config
from csql_sim.sim.executor import run_physical_episode
from csql_sim.sim.render import ReplayRenderer, caption_image, check_video_options, video_frame_count, write_video


@pytest.fixture(scope="module")
def recording():
    r = run_physical_episode(parse_config("A,B,C"), parse_config("AB,C"), seed=0, record=True, fps=10)
    assert r.success
    return r.recording


def test_recording_in_simulated_time(recording):
    r = run_physical_episode(parse_config("A,B,C"), parse_config("AB,C"), seed=0)
    expected = int(r.sim_seconds * 10)
    assert abs(len(recording.frames) - expected) <= 3
    assert recording.frames[-1].caption


def test_mp4_frames_and_size(recording, tmp_path):
    out = write_video(recording, tmp_path / "ep.mp4", 160, 120, workers=2, progress=False)
    reader = imageio.get_reader(out)
    assert reader.count_frames() == video_frame_count(recording)
    assert reader.get_meta_data()["size"] == (160, 120)
    assert [p.name for p in tmp_path.iterdir()] == ["ep.mp4"]  # no temporary file left


def test_gif(recording, tmp_path):
    out = write_video(recording, tmp_path / "ep.gif", 96, 72, workers=1, progress=False)
    frames = imageio.mimread(out)
    assert frames[0].shape[:2] == (72, 96)
    assert len(frames) >= len(recording.frames) - 1


def test_caption_changes_pixels():
    import numpy as np

    blank = np.full((120, 160, 3), 200, dtype=np.uint8)
    out = caption_image(blank, "pickup(A) S7111000ttt0000C")
    assert out.shape == blank.shape and (out != blank).any()


@pytest.mark.parametrize("args", [("v.avi", 640, 480, 30), ("v.mp4", 641, 480, 30), ("v.gif", 8, 8, 30),
                                  ("v.mp4", 640, 480, 0)])
def test_bad_video_options(args):
    with pytest.raises(CsqlError):
        check_video_options(*args)


def test_failed_render_keeps_the_old_video_and_leaves_no_temporary(recording, tmp_path, monkeypatch):
    from csql_sim.sim import render

    out = tmp_path / "ep.gif"
    out.write_bytes(b"old video")

    def broken(self, *args, **kwargs):
        raise RuntimeError("renderer crashed")

    monkeypatch.setattr(render.ReplayRenderer, "render", broken)
    with pytest.raises(RuntimeError):
        write_video(recording, out, 32, 24, workers=1, progress=False)
    assert out.read_bytes() == b"old video"
    assert [p.name for p in tmp_path.iterdir()] == ["ep.gif"]


def test_replay_renderer_owns_one_scene_per_world_and_closes_them(recording):
    renderer = ReplayRenderer()
    frames = renderer.render(recording.n, recording.config, recording.frames[:2], 32, 24)
    assert len(frames) == 2 and frames[0].shape == (24, 32, 3)
    scene = renderer.scene(recording.n, recording.config)
    assert renderer.scene(recording.n, recording.config) is scene and scene.replay_only
    renderer.close()
    assert scene.client == -1
