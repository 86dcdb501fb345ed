"""Off-screen rendering of recorded episodes into captioned .mp4 or .gif videos.

Poses are recorded during simulation (see :mod:`csql_sim.sim.recording`); frames are
rendered afterwards by worker processes, each with its own DIRECT client and a replay
scene whose bodies are set to the recorded poses. TinyRenderer is used (no EGL needed).
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import imageio.v2 as imageio
import numpy as np
from PIL import Image, ImageDraw, ImageFont
from tqdm import tqdm

from csql_sim.errors import CsqlError
from csql_sim.sim.camera import RENDER_CAMERA, Camera, capture
from csql_sim.sim.recording import Frame, Recording
from csql_sim.sim.scene import Scene

VIDEO_SUFFIXES = (".mp4", ".gif")
CAPTION_HEIGHT = 0.09  # caption strip height as a fraction of the frame height
HOLD_SECONDS = 0.5  # the last frame is repeated this long


class VideoError(CsqlError):
    """A video that cannot be written with the given options."""


def check_video_options(path: str | os.PathLike, width: int, height: int, fps: int) -> Path:
    """Validate the output path and frame settings; returns the path."""
    out = Path(path)
    if out.suffix.lower() not in VIDEO_SUFFIXES:
        raise VideoError(f"video file must end in .mp4 or .gif, got {str(out)!r}")
    if not (16 <= width <= 3840 and 16 <= height <= 2160):
        raise VideoError(f"frame size must be 16..3840 x 16..2160, got {width}x{height}")
    if out.suffix.lower() == ".mp4" and (width % 2 or height % 2):
        raise VideoError(f"mp4 frames need an even width and height, got {width}x{height}")
    if not 1 <= fps <= 120:
        raise VideoError(f"fps must be 1..120, got {fps}")
    return out


def video_frame_count(recording: Recording, fps: int | None = None) -> int:
    """Frames the video of ``recording`` will have (recorded frames plus the final hold)."""
    return len(recording.frames) + hold_frames(fps or recording.fps)


def hold_frames(fps: int) -> int:
    """Copies of the last frame appended so the end state stays visible."""
    return max(1, round(HOLD_SECONDS * fps))


def caption_image(rgb: np.ndarray, text: str) -> np.ndarray:
    """Draw ``text`` on a dark strip along the bottom of the frame."""
    img = Image.fromarray(rgb)
    h = img.height
    strip = max(12, int(h * CAPTION_HEIGHT))
    draw = ImageDraw.Draw(img)
    draw.rectangle((0, h - strip, img.width, h), fill=(20, 20, 20))
    font = ImageFont.load_default(size=max(8, int(strip * 0.6)))
    draw.text((6, h - strip + strip * 0.15), text, fill=(255, 255, 255), font=font)
    return np.asarray(img)


_REPLAY: dict[tuple[int, object], Scene] = {}  # per worker process: replay scene by (n, config)


def _replay_scene(recording_n: int, config: object) -> Scene:
    key = (recording_n, config)
    if key not in _REPLAY:
        _REPLAY[key] = Scene(recording_n, config, physics=False)  # type: ignore[arg-type]
    return _REPLAY[key]


def render_frames(n: int, config: object, frames: list[Frame], width: int, height: int,
                  camera: Camera = RENDER_CAMERA) -> list[np.ndarray]:
    """Render captioned RGB frames of a replay scene (runs inside a worker process)."""
    scene = _replay_scene(n, config)
    out = []
    for frame in frames:
        scene.apply_snapshot(frame.poses, frame.joints)
        rgb, _, _ = capture(scene, camera, width, height)
        out.append(caption_image(rgb, frame.caption))
    return out


def _chunks(frames: list[Frame], size: int) -> list[list[Frame]]:
    return [frames[i:i + size] for i in range(0, len(frames), size)]


def write_video(recording: Recording, path: str | os.PathLike, width: int = 640, height: int = 480,
                fps: int | None = None, workers: int | None = None, camera: Camera = RENDER_CAMERA,
                progress: bool = True) -> Path:
    """Render ``recording`` and write it atomically as .mp4 or .gif.

    Args:
        recording: poses recorded during an episode.
        path: output file; its suffix picks the format.
        width: frame width in pixels.
        height: frame height in pixels.
        fps: playback frame rate (default: the recording's).
        workers: rendering processes (default: every core).
        camera: the rendering view.
        progress: show a tqdm bar on stderr.

    Returns:
        The path written.
    """
    fps = fps or recording.fps
    out = check_video_options(path, width, height, fps)
    if not recording.frames:
        raise VideoError("the recording has no frames")
    workers = workers or os.cpu_count() or 1
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_name(f".{out.stem}.partial{out.suffix}")
    chunk = max(1, min(16, len(recording.frames) // (4 * workers) or 1))
    bar = tqdm(total=len(recording.frames), desc=f"render {out.name}", unit="frame", disable=not progress)
    try:
        if out.suffix.lower() == ".mp4":
            writer = imageio.get_writer(tmp, fps=fps, codec="libx264", quality=7, macro_block_size=1,
                                        format="FFMPEG", ffmpeg_params=["-preset", "ultrafast"])
        else:
            writer = imageio.get_writer(tmp, format="GIF", mode="I", duration=1000.0 / fps, loop=0)
        last = None
        with writer:
            for rgb_list in _map_chunks(recording, _chunks(recording.frames, chunk), width, height, camera,
                                        workers):
                for rgb in rgb_list:
                    writer.append_data(rgb)
                    last = rgb
                bar.update(len(rgb_list))
            for _ in range(hold_frames(fps)):
                writer.append_data(last)
        os.replace(tmp, out)
    finally:
        bar.close()
        if tmp.exists():
            tmp.unlink()
    return out


def _map_chunks(recording: Recording, chunks: list[list[Frame]], width: int, height: int, camera: Camera,
                workers: int) -> Iterator[list[np.ndarray]]:
    """Render chunks in order, in ``workers`` processes (or in-process for one worker)."""
    n, config = recording.n, recording.config
    if workers <= 1:
        for c in chunks:
            yield render_frames(n, config, c, width, height, camera)
        return
    with ProcessPoolExecutor(max_workers=workers) as pool:
        yield from pool.map(render_frames, [n] * len(chunks), [config] * len(chunks), chunks,
                            [width] * len(chunks), [height] * len(chunks), [camera] * len(chunks))
