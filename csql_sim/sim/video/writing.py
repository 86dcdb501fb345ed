"""Off-screen rendering of recorded episodes into captioned .mp4 or .gif videos.

Poses are recorded during simulation (see :mod:`csql_sim.sim.video.recording`); frames are
rendered afterwards by worker processes, each with its own DIRECT client and a replay
scene whose bodies are set to the recorded poses, drawn by the TinyRenderer or pybullet's
EGL plugin (:mod:`csql_sim.sim.video.renderer`). The frames are encoded by the writers of
:mod:`csql_sim.sim.video.encoders` (ffmpeg with timeouts, Pillow), whose failures are one line.
"""

from __future__ import annotations

import multiprocessing
import os
from collections import deque
from collections.abc import Iterator, Sequence
from concurrent.futures import Future
from pathlib import Path

import imageio.v2 as imageio
import numpy as np
from PIL import Image, ImageDraw, ImageFont
from tqdm import tqdm

from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import atomic_output, check_output_file
from csql_sim.infra.workers import worker_count, worker_pool
from csql_sim.sim.perception.camera import Camera, capture, render_camera
from csql_sim.sim.video.encoders import EncoderError, FfmpegWriter, GifWriter
from csql_sim.sim.video.recording import Frame, Recording
from csql_sim.sim.video.renderer import close_quietly, resolve_renderer
from csql_sim.sim.video.replay import apply_snapshot, replay_scene
from csql_sim.sim.world.config import SimConfig
from csql_sim.sim.world.legend import draw_legend, legend_names
from csql_sim.sim.world.scene import Scene

VIDEO_SUFFIXES = (".mp4", ".gif")
CAPTION_HEIGHT = 0.09  # caption strip height as a fraction of the frame height
HOLD_SECONDS = 0.5  # the last frame is repeated this long
CHUNKS_IN_FLIGHT = 2  # chunks per rendering worker submitted ahead of the one the encoder waits for


class VideoError(CsqlError):
    """A video that cannot be written with the given options."""


def check_video_options(path: str | os.PathLike, width: int, height: int, fps: int) -> Path:
    """Validate the output path (a writable regular file) and frame settings; returns the path."""
    out = Path(path)
    if out.suffix.lower() not in VIDEO_SUFFIXES:
        raise VideoError(f"video file must end in .mp4 or .gif, got {str(out)!r}")
    if not (16 <= width <= 3840 and 16 <= height <= 2160):
        raise VideoError(f"frame size must be 16..3840 x 16..2160, got {width}x{height}")
    if out.suffix.lower() == ".mp4" and (width % 2 or height % 2):
        raise VideoError(f"mp4 frames need an even width and height, got {width}x{height}")
    if not 1 <= fps <= 120:
        raise VideoError(f"fps must be 1..120, got {fps}")
    check_output_file(out, "video file")
    return out


def video_frame_count(recording: Recording, fps: int | None = None) -> int:
    """Frames the video of ``recording`` will have (recorded frames plus the final hold)."""
    return len(recording.frames) + hold_frames(fps or recording.fps)


def hold_frames(fps: int) -> int:
    """Copies of the last frame appended so the end state stays visible."""
    return max(1, round(HOLD_SECONDS * fps))


def caption_image(rgb: np.ndarray, text: str, legend: int | Sequence[str] = 0, full: bool = False) -> np.ndarray:
    """Draw ``text`` on a dark strip along the bottom, and the cubes' legend along the top.

    ``legend``: the cubes' names in cube order (or a count: the letters A, B, ...); each is
    drawn beside its colour's square, with the colour word when ``full``
    (:func:`csql_sim.sim.world.legend.draw_legend`).
    """
    img = Image.fromarray(rgb)
    h = img.height
    strip = max(12, int(h * CAPTION_HEIGHT))
    draw = ImageDraw.Draw(img)
    draw.rectangle((0, h - strip, img.width, h), fill=(20, 20, 20))
    caption_font, text = fit_caption(draw, text, img.width - 12, max(8, int(strip * 0.6)))
    draw.text((6, h - strip + strip * 0.15), text, fill=(255, 255, 255), font=caption_font)
    names = legend_names(legend) if isinstance(legend, int) else tuple(legend)
    if names:
        draw_legend(draw, img.width, max(8, strip * 0.6), names, full)
    return np.asarray(img)


def fit_caption(draw: ImageDraw.ImageDraw, text: str, width: float, size: int,
                smallest: int = 8) -> tuple[ImageFont.ImageFont, str]:
    """A font (``size`` or smaller, down to ``smallest``) and text that fit ``width`` pixels.

    A long caption (a 6-block tower's state, a long failure reason) first gets a smaller
    font; if it still does not fit, it is cut with an ellipsis, never drawn past the frame.
    """
    for points in range(size, smallest - 1, -1):
        font = ImageFont.load_default(size=points)
        if draw.textlength(text, font=font) <= width:
            return font, text
    while text and draw.textlength(text + "...", font=font) > width:
        text = text[:-1]
    return font, text + "..."


class ReplayRenderer:
    """Renders captioned frames of recordings; owns one replay scene per (n, config).

    Each rendering worker process owns exactly one, made by the pool's initializer
    (:func:`_init_render_worker`) and held in that process's ``_WORKER_RENDERER``; it
    lives as long as the worker. In-process rendering makes its own and closes it.

    Args:
        renderer: ``"tiny"`` or ``"egl"`` (resolved: :func:`csql_sim.sim.video.renderer.resolve_renderer`).
    """

    def __init__(self, renderer: str = "tiny") -> None:
        self.renderer = renderer
        self._scenes: dict[tuple[int, SimConfig], Scene] = {}

    def scene(self, n: int, config: SimConfig) -> Scene:
        """The replay scene of ``n`` cubes and ``config`` (built on first use)."""
        key = (n, config)
        if key not in self._scenes:
            self._scenes[key] = replay_scene(n, config, self.renderer)
        return self._scenes[key]

    def render(self, n: int, config: SimConfig, frames: list[Frame], width: int, height: int,
               camera: Camera | None = None, total: int = 0, names: Sequence[str] | None = None) -> list[np.ndarray]:
        """Captioned RGB frames: the replay scene set to each frame's poses, seen by ``camera``.

        Captions read ``step k/K  <what>  <message>`` with K = ``total`` (the episode's
        actions); a legend along the top names the ``n`` cubes (``names``, default their
        letters), with their colour words in the frames before the first action.
        """
        names = legend_names(n, names)
        scene = self.scene(n, config)
        camera = render_camera(n) if camera is None else camera
        out = []
        for frame in frames:
            apply_snapshot(scene, frame.poses, frame.joints)
            rgb, _, _ = capture(scene, camera, width, height)
            out.append(caption_image(rgb, frame.caption.text(total), legend=names, full=frame.caption.step == 0))
        return out

    def close(self) -> None:
        """Release every replay scene's physics client."""
        for scene in self._scenes.values():
            close_quietly(scene)
        self._scenes.clear()


_WORKER_RENDERER: ReplayRenderer | None = None  # the one renderer of a rendering worker process


def _init_render_worker(renderer: str) -> None:
    global _WORKER_RENDERER
    _WORKER_RENDERER = ReplayRenderer(renderer)


def _render_in_worker(n: int, config: SimConfig, frames: list[Frame], width: int, height: int,
                      camera: Camera, total: int, names: tuple[str, ...] | None) -> list[np.ndarray]:
    assert _WORKER_RENDERER is not None, "rendering worker started without _init_render_worker"
    return _WORKER_RENDERER.render(n, config, frames, width, height, camera, total, names)


def _chunks(frames: list[Frame], size: int) -> list[list[Frame]]:
    return [frames[i:i + size] for i in range(0, len(frames), size)]


def _open_writer(path: Path, fps: int, suffix: str) -> FfmpegWriter | GifWriter:
    """The writer of ``path`` in the format of ``suffix`` (.mp4: ffmpeg's libx264, .gif: Pillow)."""
    return FfmpegWriter(path, fps) if suffix == ".mp4" else GifWriter(path, fps)


def write_video(recording: Recording, path: str | os.PathLike, width: int = 640, height: int = 480,
                fps: int | None = None, workers: int | None = None, camera: Camera | None = None,
                progress: bool = True, renderer: str = "auto") -> Path:
    """Render ``recording`` and write it atomically (:func:`csql_sim.infra.files.atomic_output`) as .mp4 or .gif.

    The video is read back from the temporary file (:func:`verify_video`) before it
    replaces anything: an encoder that died half way (a full disk, a file size limit)
    fails with a VideoError and leaves an existing file at ``path`` as it was.

    Args:
        recording: poses recorded during an episode.
        path: output file; its suffix picks the format.
        width: frame width in pixels.
        height: frame height in pixels.
        fps: playback frame rate (default: the recording's).
        workers: rendering processes (default: every core; at most the cores and one per chunk of frames).
        camera: the rendering view (default: :func:`~csql_sim.sim.perception.camera.render_camera` of the cube count).
        progress: show a tqdm bar on stderr.
        renderer: ``"tiny"``, ``"egl"`` or ``"auto"`` (EGL where its plugin loads).

    Returns:
        The path written.
    """
    fps = fps or recording.fps
    camera = render_camera(recording.n) if camera is None else camera
    out = check_video_options(path, width, height, fps)
    renderer = resolve_renderer(renderer)
    if not recording.frames:
        raise VideoError("the recording has no frames")
    cores = worker_count(workers, len(recording.frames))  # at most the cores
    chunks = _chunks(recording.frames, max(1, min(16, len(recording.frames) // (4 * cores) or 1)))
    # the bar counts the frames of the file: the recorded ones and the final hold
    bar = tqdm(total=video_frame_count(recording, fps), desc=f"render {out.name}", unit="frame",
               disable=not progress)
    rendered = _map_chunks(recording, chunks, width, height, camera, worker_count(workers, len(chunks)), renderer)
    suffix = out.suffix.lower()
    try:
        with atomic_output(out) as tmp:
            with _open_writer(tmp, fps, suffix) as writer:
                last = None
                for rgb_list in rendered:
                    for rgb in rgb_list:
                        writer.append_data(rgb)
                        last = rgb
                    bar.update(len(rgb_list))
                for _ in range(hold_frames(fps)):
                    writer.append_data(last)
                    bar.update(1)
            verify_video(tmp, suffix, video_frame_count(recording, fps), out)
    except (OSError, EncoderError) as exc:  # a full disk, an encoder that failed or stopped
        raise VideoError(f"cannot write video {str(out)!r} ({_reason(exc)})") from None
    finally:
        rendered.close()  # ends the rendering workers if the encoder failed
        bar.close()
    return out


def _reason(exc: OSError | EncoderError) -> str:
    """Why a write failed, in a few words: an OSError's own text (no errno), else the first line."""
    if isinstance(exc, OSError) and exc.strerror:
        return exc.strerror
    return _first_line(exc)


def _first_line(exc: BaseException) -> str:
    """The first non-blank line of ``exc``'s message (encoders print many), or its type's name."""
    return next((line.strip() for line in str(exc).splitlines() if line.strip()), exc.__class__.__name__)


def verify_video(path: Path, suffix: str, frames: int, shown: Path | None = None) -> None:
    """Read the video at ``path`` back; a VideoError unless it is whole.

    An .mp4 must have exactly ``frames`` frames. A .gif must decode to its end, end with the
    GIF trailer and have 1..``frames`` frames (Pillow merges identical consecutive frames,
    e.g. the final hold, into one of a longer duration).

    Args:
        path: the file written (the temporary file of :func:`write_video`).
        suffix: ``".mp4"`` or ``".gif"``.
        frames: the frames the encoder was given.
        shown: the name to report (default ``path``).
    """
    name = str(shown or path)
    try:
        found = _frames_read_back(path, suffix)
    except Exception as exc:  # whatever the reader fails with, the video is broken
        raise VideoError(f"cannot write video {name!r}: the file written is not a whole video "
                         f"({_first_line(exc)}); nothing was written") from None
    whole = found == frames if suffix == ".mp4" else 1 <= found <= frames
    if not whole:
        raise VideoError(f"cannot write video {name!r}: {found} frames read back of {frames} written "
                         f"(the encoder stopped early?); nothing was written")


def _frames_read_back(path: Path, suffix: str) -> int:
    """The frames imageio reads from the video at ``path``; raises if it cannot read it to the end."""
    if suffix == ".mp4":
        _check_mp4_boxes(path)
        with imageio.get_reader(path, format="FFMPEG") as reader:
            return reader.count_frames()
    with imageio.get_reader(path, format="GIF") as reader:
        found = sum(1 for _ in reader)
    with open(path, "rb") as fh:
        fh.seek(-1, os.SEEK_END)
        if fh.read(1) != b";":
            raise VideoError("no GIF trailer: the file is cut short")
    return found


def _check_mp4_boxes(path: Path) -> None:
    """Raise unless the top-level boxes of the .mp4 at ``path`` tile it exactly and include moov and mdat.

    ffmpeg's exit status is not reported by imageio: an encoder killed while writing its
    last box (the index, ``moov``, comes last) leaves a file whose frames may still be
    counted, but whose last box runs past the end of the file.
    """
    size, at, kinds = path.stat().st_size, 0, set()
    with open(path, "rb") as fh:
        while at < size:
            fh.seek(at)
            head = fh.read(16)
            box, kind = int.from_bytes(head[:4], "big"), head[4:8]
            if box == 1 and len(head) == 16:  # a 64-bit size follows the type
                box = int.from_bytes(head[8:16], "big")
            elif box == 0:  # the box runs to the end of the file
                box = size - at
            if len(head) < 8 or box < 8 or at + box > size:
                raise VideoError(f"the file is cut short (box {kind.decode('latin-1')!r} at byte {at})")
            kinds.add(kind)
            at += box
    if not {b"moov", b"mdat"} <= kinds:
        raise VideoError("no moov or mdat box: not a whole mp4 file")


def _map_chunks(recording: Recording, chunks: list[list[Frame]], width: int, height: int, camera: Camera,
                workers: int, renderer: str) -> Iterator[list[np.ndarray]]:
    """Render chunks in order, in ``workers`` processes (or in-process for one worker).

    At most :data:`CHUNKS_IN_FLIGHT` chunks per worker are queued or rendered ahead of the
    encoder (not every frame of the video at once). Futures are never cancelled here: when
    the encoder fails or on Ctrl-C, the pool is stopped (:func:`~csql_sim.infra.workers.stop_pool`).
    """
    n, config, total, names = recording.n, recording.config, recording.actions, recording.names
    if workers <= 1:
        replay = ReplayRenderer(renderer)
        try:
            for c in chunks:
                yield replay.render(n, config, c, width, height, camera, total, names)
        finally:
            replay.close()
        return
    # EGL workers are spawned: a process that has started EGL (llvmpipe's threads) cannot fork safely
    context = multiprocessing.get_context("spawn") if renderer == "egl" else None
    with worker_pool(workers, _init_render_worker, (renderer,), mp_context=context) as pool:
        pending: deque[Future] = deque()
        for chunk in chunks:
            pending.append(pool.submit(_render_in_worker, n, config, chunk, width, height, camera, total, names))
            if len(pending) >= CHUNKS_IN_FLIGHT * workers:
                yield pending.popleft().result()
        while pending:
            yield pending.popleft().result()
