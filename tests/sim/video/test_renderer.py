import subprocess
import sys

import imageio.v2 as imageio
import numpy as np
import pytest

from csql_sim.core.state.notation import parse_config
from csql_sim.sim.control.executor import run_physical_episode
from csql_sim.sim.perception.camera import RENDER_CAMERA, capture
from csql_sim.sim.video.renderer import (
    RendererError,
    close_quietly,
    egl_available,
    egl_on_gpu,
    egl_plugin_path,
    resolve_renderer,
)
from csql_sim.sim.video.replay import apply_snapshot, replay_scene
from csql_sim.sim.video.writing import CAPTION_HEIGHT, video_frame_count, write_video

needs_egl = pytest.mark.skipif(
    not egl_available(),
    reason="pybullet's eglRenderer plugin does not load here "
    + ("(no eglRenderer module)" if egl_plugin_path() is None else "(no EGL display, not even Mesa's)"),
)


@pytest.fixture(scope="module")
def recording():
    r = run_physical_episode(parse_config("A,B,C"), parse_config("AB,C"), seed=0, record=True, fps=10)
    assert r.success
    return r.recording


def test_resolve_renderer():
    assert resolve_renderer("tiny") == "tiny"
    assert resolve_renderer("flat") == "flat"
    assert resolve_renderer("auto") == ("egl" if egl_on_gpu() else "flat")
    with pytest.raises(RendererError, match="--renderer must be one of"):
        resolve_renderer("vulkan")


@pytest.mark.skipif(egl_available(), reason="EGL loads here; the refusal is for machines without it")
def test_egl_refused_in_one_line_where_it_cannot_load():
    with pytest.raises(RendererError, match="eglRenderer plugin did not load"):
        resolve_renderer("egl")


def _scene_pixels(rgb: np.ndarray) -> np.ndarray:
    """The frame above the caption strip."""
    return rgb[: int(rgb.shape[0] * (1 - CAPTION_HEIGHT)) - 2]


@needs_egl
def test_egl_video_is_readable_and_shows_the_scene(recording, tmp_path):
    out = write_video(recording, tmp_path / "egl.mp4", 160, 120, workers=2, progress=False, renderer="egl")
    reader = imageio.get_reader(out)
    assert reader.count_frames() == video_frame_count(recording)
    frame = reader.get_data(len(recording.frames) // 2)
    assert frame.shape == (120, 160, 3)
    colours = np.unique(_scene_pixels(frame).reshape(-1, 3) // 8, axis=0)
    assert len(colours) > 40, "an EGL frame of the scene, not an empty background"


@needs_egl
def test_render_egl_in_process_keeps_stdout_to_the_report(tmp_path):
    """The plugin's own prints (device, driver, "Destroy EGL OpenGL window.") never reach stdout."""
    out = tmp_path / "v.gif"
    done = subprocess.run([sys.executable, "-m", "csql_sim", "render", "--start", "A,B", "--goal", "AB",
                           "--out", str(out), "--width", "64", "--height", "48", "--fps", "5", "--workers", "1",
                           "--renderer", "egl"], capture_output=True, text=True, timeout=240, check=False)
    assert done.returncode == 0, done.stderr
    assert not [line for line in done.stdout.splitlines() if "EGL" in line or "ven =" in line], done.stdout
    assert done.stdout.splitlines()[-1].startswith(f"wrote {out}")
    assert len(imageio.mimread(out)) >= 2


@needs_egl
def test_egl_and_tiny_frame_the_scene_alike(recording):
    """Same camera: the cubes appear at the same pixels in both renderers."""
    frame = recording.frames[-1]
    masks = []
    for renderer in ("tiny", "egl"):
        scene = replay_scene(recording.n, recording.config, renderer)
        try:
            apply_snapshot(scene, frame.poses, frame.joints)
            rgb = capture(scene, RENDER_CAMERA, 160, 120)[0].astype(int)
            scene.set_block_pose(0, (0.0, 0.0, -1.0), (0.0, 0.0, 0.0, 1.0))  # cube A out of view
            without = capture(scene, RENDER_CAMERA, 160, 120)[0].astype(int)
            cube = np.abs(rgb - without).sum(axis=-1) > 30  # the pixels each renderer draws cube A on
        finally:
            close_quietly(scene)
        assert cube.sum() > 10
        masks.append(cube)
    rows = [np.nonzero(m)[0].mean() for m in masks]
    cols = [np.nonzero(m)[1].mean() for m in masks]
    assert abs(rows[0] - rows[1]) < 3 and abs(cols[0] - cols[1]) < 3


def test_the_flat_painter_draws_the_cubes_where_pybullet_does(recording):
    """The painter's projection and poses agree with the TinyRenderer's: each cube's pixels in the same place."""
    from csql_sim.sim.video.painter import Painter, Projection

    frame = recording.frames[len(recording.frames) // 2]
    scene = replay_scene(recording.n, recording.config, "tiny")
    try:
        apply_snapshot(scene, frame.poses, frame.joints)
        tiny = capture(scene, RENDER_CAMERA, 320, 240)[0].astype(int)
        painter = Painter(recording.n, recording.config, recording.arm)
        flat = np.asarray(painter.paint(frame.poses, frame.links, Projection.of(RENDER_CAMERA, 320, 240)))
    finally:
        close_quietly(scene)
    for rgb in ((217, 38, 38), (38, 178, 51), (38, 76, 217)):  # cubes A, B, C: red, green, blue
        masks = []
        for img in (tiny, flat.astype(int)):
            hue = np.abs(img - np.asarray(rgb)).sum(axis=2)
            near = hue < 0.5 * np.abs(np.asarray(rgb) - np.asarray(rgb).mean()).sum() + 60
            dominant = np.argmax(img, axis=2) == int(np.argmax(rgb))
            masks.append(near & dominant & (img.max(axis=2) - img.min(axis=2) > 60))
        assert masks[0].sum() > 20 and masks[1].sum() > 20
        for axis in (0, 1):
            a, b = (np.nonzero(m)[axis].mean() for m in masks)
            assert abs(a - b) < 3, (rgb, axis, a, b)
