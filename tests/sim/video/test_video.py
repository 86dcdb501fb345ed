from dataclasses import replace

import imageio.v2 as imageio
import pytest

from csql_sim.core.state.notation import parse_config
from csql_sim.infra.errors import CsqlError
from csql_sim.sim.control.executor import run_physical_episode
from csql_sim.sim.video.writing import (
    ReplayRenderer,
    caption_image,
    check_video_options,
    render_frames,
    video_frame_count,
    video_view,
    write_video,
)


@pytest.fixture(scope="module")
def recording():
    r = run_physical_episode(parse_config("A,B,C"), parse_config("AB,C"), seed=0, record=True, fps=10)
    assert r.success
    return r.recording


def test_recording_in_simulated_time(recording):
    r = run_physical_episode(parse_config("A,B,C"), parse_config("AB,C"), seed=0)
    expected = int(r.sim_seconds * 10)
    assert abs(len(recording.frames) - expected) <= 3
    # every caption reads "step k/K  <what>  <message>"; the first names the start and the goal
    total = recording.actions
    assert total == r.length == 2
    from csql_sim.core.state.message import format_state_message
    from csql_sim.core.state.world import BlocksWorld

    start_message = format_state_message(parse_config("A,B,C"), BlocksWorld.of(3).state_index(parse_config("AB,C")))
    texts = [f.caption.text(total) for f in recording.frames]
    assert texts[0] == f"step 0/2  start A,B,C  goal AB,C  {start_message}"
    assert texts[-1].startswith("step 2/2  goal AB,C  reached  S")
    assert all(t.startswith("step ") and f"/{total}  " in t for t in texts)
    assert {"step 1/2  pickup(B)", "step 2/2  stack(B,A)"} <= {t[:20].rstrip() for t in texts}
    named = {f.caption.text(total, ("ruby", "jade", "b2")) for f in recording.frames}
    assert any(t.startswith("step 2/2  (stack jade ruby)  S") for t in named)
    assert any(t.startswith("step 0/2  start ruby, jade, b2  goal ruby jade, b2  S") for t in named)


def test_the_caption_shows_the_message_the_step_table_prints():
    """During an action the caption's message is the one the policy saw: the step record's, not another."""
    r = run_physical_episode(parse_config("CBA"), parse_config("ABC"), seed=0, record=True, fps=5)
    assert r.success and r.length >= 4
    for k, step in enumerate(r.steps):
        shown = {f.caption.message for f in r.recording.frames if f.caption.step == k + 1 and f.caption.action}
        assert shown == {step.message}


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


def test_render_cli_prints_the_file_frame_count_and_writes_provenance(tmp_path, capsys):
    import json

    from csql_sim.cli import main

    out = tmp_path / "v.mp4"
    code = main(["render", "--start", "A,B,C", "--goal", "AB,C", "--out", str(out), "--width", "96",
                 "--height", "72", "--fps", "10", "--workers", "1", "--quiet"])
    printed = capsys.readouterr().out
    frames = imageio.get_reader(out).count_frames()
    assert code == 0 and f"({frames} frames at 10 fps" in printed
    sidecar = json.loads((tmp_path / "v.mp4.json").read_text())
    assert sidecar["video"]["frames"] == frames and sidecar["parameters"]["start"] == "A,B,C"
    assert sidecar["parameters"]["rules"] == {"file": None, "sha256": None} and sidecar["version"]


def test_caption_changes_pixels():
    import numpy as np

    blank = np.full((120, 160, 3), 200, dtype=np.uint8)
    out = caption_image(blank, "pickup(A) S7111000ttt0000C")
    assert out.shape == blank.shape and (out != blank).any()
    # the legend: a red square for A, then a green one for B, along the top
    legend = caption_image(blank, "x", legend=2)
    top = [tuple(p) for p in legend[6, :80]]
    assert top[6] == (216, 38, 38) and (38, 178, 51) in top[20:]
    assert top.index((38, 178, 51)) > top.index((216, 38, 38))
    # named cubes: the names (and, before the first action, the colour words) take more room
    named = caption_image(blank, "x", legend=["ruby", "jade"])
    full = caption_image(blank, "x", legend=["ruby", "jade"], full=True)
    green_at = [[tuple(p) for p in img[6]].index((38, 178, 51)) for img in (legend, named, full)]
    assert green_at[0] < green_at[1] < green_at[2]


def _changed_near(changed, xy, radius=8):
    """Changed pixels within ``radius`` of each point."""
    return [int(changed[max(0, int(y) - radius):int(y) + radius, max(0, int(x) - radius):int(x) + radius].sum())
            for x, y in xy]


@pytest.mark.parametrize("renderer", ["flat", "tiny"])
def test_frames_name_each_cube_where_it_is_seen(recording, renderer):
    import numpy as np

    from csql_sim.sim.video.painter import Projection

    frame = recording.frames[-1]
    replay = ReplayRenderer(renderer)
    try:
        view = video_view(recording, 320, 240, top=False)
        named = replay.render(3, recording.config, [frame], replace(view, names=("ruby", "jade", "b2")))[0]
        blank = replay.render(3, recording.config, [frame], replace(view, names=("", "", "")))[0]
    finally:
        replay.close()
    changed = (named != blank).any(axis=2)
    xy, _ = Projection.of(view.camera, 320, 240)(np.asarray([p.position for p in frame.poses]))
    assert min(_changed_near(changed, xy)) >= 10, "every cube's name is written on it"
    far = changed.sum() - sum(_changed_near(changed, xy, radius=30))
    assert far <= 0, "and nowhere else"


def test_one_worker_and_two_write_the_same_frames_and_file(recording, tmp_path):
    """Frames depend on the recording alone, not on how many processes render them."""
    one = write_video(recording, tmp_path / "one.mp4", 160, 120, workers=1, progress=False, renderer="flat")
    two = write_video(recording, tmp_path / "two.mp4", 160, 120, workers=2, progress=False, renderer="flat")
    frames_one, frames_two = imageio.mimread(one, memtest=False), imageio.mimread(two, memtest=False)
    assert len(frames_one) == len(frames_two) == video_frame_count(recording)
    assert all((a == b).all() for a, b in zip(frames_one, frames_two, strict=True))
    raw = [list(render_frames(recording, video_view(recording, 160, 120), workers=w, renderer="flat"))
           for w in (1, 2)]
    assert len(raw[0]) == len(recording.frames)
    assert all(a.tobytes() == b.tobytes() for a, b in zip(*raw, strict=True))
    assert one.read_bytes() == two.read_bytes()


def test_render_camera_sees_the_whole_arm(recording):

    from csql_sim.sim.perception.camera import RENDER_CAMERA, capture
    from csql_sim.sim.video.replay import apply_snapshot, replay_scene

    with replay_scene(recording.n, recording.config) as scene:
        panda = scene.bodies["panda"]
        for frame in recording.frames[::3]:
            apply_snapshot(scene, frame.poses, frame.joints)
            _, _, seg = capture(scene, RENDER_CAMERA, 160, 120, segmentation=True)
            arm = (seg & ((1 << 24) - 1)) == panda
            assert arm.any()
            # the arm never touches the top, left or right border: nothing of it is cut off
            assert not (arm[0, :].any() or arm[:, 0].any() or arm[:, -1].any())


@pytest.mark.parametrize("args", [("v.avi", 640, 480, 30), ("v.mp4", 641, 480, 30), ("v.gif", 8, 8, 30),
                                  ("v.mp4", 640, 480, 0)])
def test_bad_video_options(args):
    with pytest.raises(CsqlError):
        check_video_options(*args)


def test_failed_render_keeps_the_old_video_and_leaves_no_temporary(recording, tmp_path, monkeypatch):
    from csql_sim.sim.video import writing as render

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
    renderer = ReplayRenderer("tiny")
    frames = renderer.render(recording.n, recording.config, recording.frames[:2], video_view(recording, 32, 24))
    assert len(frames) == 2 and frames[0].shape == (24, 32, 3)
    scene = renderer.scene(recording.n, recording.config)
    assert renderer.scene(recording.n, recording.config) is scene and scene.replay_only
    renderer.close()
    assert scene.client == -1


def test_a_long_caption_stays_inside_the_frame():
    """A 6-block tower's caption ran off the right edge: it now shrinks, then is cut with '...'."""
    import numpy as np
    from PIL import Image, ImageDraw

    from csql_sim.sim.video.frames import fit_caption

    draw = ImageDraw.Draw(Image.new("RGB", (320, 40)))
    long = "step 12/16  stack(F,E)  S0000001edcba0F  FEDCBA -> ABCDEF  perception: camera, nudged"
    font, text = fit_caption(draw, long, 308, 16)
    assert draw.textlength(text, font=font) <= 308
    short_font, short = fit_caption(draw, "step 1", 308, 16)
    assert short == "step 1" and short_font.size == 16
    frame = caption_image(np.zeros((240, 320, 3), np.uint8), long)
    assert frame.shape == (240, 320, 3)


def test_the_progress_bar_counts_the_frames_of_the_file(recording, tmp_path, monkeypatch):
    """Issue 28 item 16: the bar counted the recorded frames (201) while the file had the final hold too (216)."""
    import csql_sim.sim.video.writing as video

    bars = []

    class Bar:
        def __init__(self, total, **_):
            self.total, self.n = total, 0
            bars.append(self)

        def update(self, k):
            self.n += k

        def close(self):
            pass

    monkeypatch.setattr(video, "tqdm", Bar)
    out = write_video(recording, tmp_path / "ep.mp4", 160, 120, workers=1, progress=True)
    frames = imageio.get_reader(out).count_frames()
    assert [(bar.total, bar.n) for bar in bars] == [(frames, frames)]
    assert frames > len(recording.frames)  # the final hold is counted
