"""Off-screen rendering of recorded episodes into captioned .mp4 or .gif videos.

Poses are recorded during simulation (see :mod:`csql_sim.sim.recording`); frames are
rendered afterwards by worker processes, each with its own DIRECT client and a replay
scene whose bodies are set to the recorded poses, drawn by the TinyRenderer or pybullet's
EGL plugin (:mod:`csql_sim.sim.renderer`). The frames are encoded by the writers of
:mod:`csql_sim.sim.video_writers` (ffmpeg with timeouts, Pillow), whose failures are one line.
"""

from __future__ import annotations

import multiprocessing
import os
from collections import deque
from collections.abc import Iterator, Sequence
from concurrent.futures import Future
from dataclasses import dataclass
from functools import cache, lru_cache
from pathlib import Path

import imageio.v2 as imageio
import numpy as np
from PIL import Image, ImageDraw, ImageFont
from tqdm import tqdm

from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import atomic_output, check_output_file
from csql_sim.infra.workers import worker_count, worker_pool
from csql_sim.sim.camera import Camera, capture
from csql_sim.sim.config import SimConfig
from csql_sim.sim.framing import goal_camera, top_camera
from csql_sim.sim.legend import draw_labels, draw_legend, legend_names
from csql_sim.sim.painter import ArmShape, Painter, Projection
from csql_sim.sim.recording import Frame, Recording
from csql_sim.sim.renderer import close_quietly, resolve_renderer
from csql_sim.sim.replay import apply_snapshot, replay_scene
from csql_sim.sim.scene import Scene
from csql_sim.sim.video_writers import EncoderError, FfmpegWriter, GifWriter

VIDEO_SUFFIXES = (".mp4", ".gif")
CAPTION_HEIGHT = 0.09  # caption strip height as a fraction of the frame height
HOLD_SECONDS = 2.0  # the last frame is repeated this long, to be read
FRAMING_STRIDE = 8  # every 8th frame's cubes are kept in the picture too
FRAMES_PER_WORKER = 150  # the flat painter's frames worth starting a rendering process for (by default)
PROGRESS_DELAY = 1.0  # seconds before a bar shows: phases under a second stay silent
CHUNKS_IN_FLIGHT = 2  # chunks per rendering worker submitted ahead of the one the encoder waits for


class VideoError(CsqlError):
    """A video that cannot be written with the given options."""


@dataclass(frozen=True)
class VideoOptions:
    """How a video is made: one set of options for ``render``, ``execute`` and ``demo``.

    The defaults suit a CPU-only machine: the flat painter (unless EGL runs on a GPU),
    24 frames per second of video, twice real time.

    Attributes:
        width: frame width in pixels, 16..3840 (an even number for .mp4).
        height: frame height in pixels, 16..2160 (an even number for .mp4).
        fps: frames per second of video, 1..120.
        speed: simulated seconds per second of video, 0.25..16 (2: a time-lapse at twice real time).
        renderer: ``"auto"``, ``"flat"``, ``"tiny"`` or ``"egl"`` (:func:`~csql_sim.sim.renderer.resolve_renderer`).
        workers: rendering processes (None: the cores, at most one per chunk of frames).
    """

    width: int = 640
    height: int = 480
    fps: int = 24
    speed: float = 2.0
    renderer: str = "auto"
    workers: int | None = None

    @property
    def sample_rate(self) -> float:
        """Frames recorded per simulated second: ``fps / speed``."""
        return self.fps / self.speed

    def check(self, path: str | os.PathLike) -> Path:
        """Validate the options and the output path (:func:`check_video_options`); returns the path."""
        if not 0.25 <= self.speed <= 16:
            raise VideoError(f"speed must be 0.25..16 simulated seconds per second of video, got {self.speed:g}")
        return check_video_options(path, self.width, self.height, self.fps)


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
    """Draw ``text`` on a dark strip along the bottom (and, if given, the cubes' legend along the top).

    ``legend``: the cubes' names in cube order (or a count: the letters A, B, ...); each is
    drawn beside its colour's square, with the colour word when ``full``
    (:func:`csql_sim.sim.legend.draw_legend`). Videos name the cubes on the cubes instead.
    """
    img = Image.fromarray(rgb)
    strip = caption_strip(text, img.width, img.height)
    img.paste(strip, (0, img.height - strip.height))
    names = legend_names(legend) if isinstance(legend, int) else tuple(legend)
    if names:
        draw_legend(ImageDraw.Draw(img), img.width, max(8, strip.height * 0.6), names, full)
    return np.asarray(img)


@lru_cache(maxsize=64)
def caption_strip(text: str, width: int, height: int) -> Image.Image:
    """The caption strip of a ``width`` x ``height`` frame (drawn once per caption: frames share them)."""
    strip = max(12, int(height * CAPTION_HEIGHT))
    img = Image.new("RGB", (width, strip), (20, 20, 20))
    draw = ImageDraw.Draw(img)
    caption_font, text = fit_caption(draw, text, width - 12, max(8, int(strip * 0.6)))
    draw.text((6, strip * 0.15), text, fill=(255, 255, 255), font=caption_font)
    return img


def fit_caption(draw: ImageDraw.ImageDraw, text: str, width: float, size: int,
                smallest: int = 8) -> tuple[ImageFont.ImageFont, str]:
    """A font (``size`` or smaller, down to ``smallest``) and text that fit ``width`` pixels.

    A long caption (a 6-block tower's state, a long failure reason) first gets a smaller
    font; if it still does not fit, it is cut with an ellipsis, never drawn past the frame.
    """
    for points in range(size, smallest - 1, -1):
        font = _font(points)
        if draw.textlength(text, font=font) <= width:
            return font, text
    while text and draw.textlength(text + "...", font=font) > width:
        text = text[:-1]
    return font, text + "..."


@dataclass(frozen=True)
class View:
    """What every frame of one video is drawn with (the same in every rendering process).

    Attributes:
        width: frame width in pixels.
        height: frame height in pixels.
        camera: the main view (:func:`~csql_sim.sim.framing.goal_camera` of the recording by default).
        top: the second view, inset in the top right corner (None: none).
        names: the cubes' names, written on the cubes.
        total: the episode's actions (K of the captions).
        captions: the names the captions use (None: the cube letters).
        arm: the Panda's shape the flat painter draws (the recording's).
    """

    width: int
    height: int
    camera: Camera
    top: Camera | None
    names: tuple[str, ...]
    total: int
    captions: tuple[str, ...] | None = None
    arm: ArmShape | None = None


def inset_size(width: int, height: int) -> tuple[int, int]:
    """The top view's size: a third of the frame's width and height."""
    return max(8, width // 3), max(8, height // 3)


@cache
def _font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    return ImageFont.load_default(size=size)


class ReplayRenderer:
    """Renders captioned frames of recordings; owns one replay scene (and painter) per (n, config).

    Each rendering worker process owns exactly one, made by the pool's initializer
    (:func:`_init_render_worker`) and held in that process's ``_WORKER_RENDERER``; it
    lives as long as the worker. In-process rendering makes its own and closes it.

    Args:
        renderer: ``"flat"``, ``"tiny"`` or ``"egl"`` (resolved: :func:`csql_sim.sim.renderer.resolve_renderer`).
    """

    def __init__(self, renderer: str = "flat") -> None:
        self.renderer = renderer
        self._scenes: dict[tuple[int, SimConfig], Scene] = {}

    def scene(self, n: int, config: SimConfig) -> Scene:
        """The replay scene of ``n`` cubes and ``config`` (built on first use; pybullet's renderers only)."""
        key = (n, config)
        if key not in self._scenes:
            self._scenes[key] = replay_scene(n, config, self.renderer)
        return self._scenes[key]

    def render(self, n: int, config: SimConfig, frames: list[Frame], view: View) -> list[np.ndarray]:
        """Captioned RGB frames: each frame's poses seen by ``view.camera``, the cubes named, the top view inset.

        Captions read ``step k/K  <what>  <message>`` with K = ``view.total``.
        """
        painter = Painter(n, config, view.arm)
        main = Projection.of(view.camera, view.width, view.height)
        top = None if view.top is None else Projection.of(view.top, *inset_size(view.width, view.height))
        cube = config.physics.cube_size
        out = []
        for frame in frames:
            if self.renderer == "flat":
                img = painter.paint(frame.poses, frame.links, main)
            else:
                scene = self.scene(n, config)
                apply_snapshot(scene, frame.poses, frame.joints)
                img = Image.fromarray(capture(scene, view.camera, view.width, view.height)[0])
            xy, depth = main(np.asarray([p.position for p in frame.poses], dtype=float))
            draw_labels(img, xy, depth, view.names, main.focal * cube / np.maximum(depth, 1e-6))
            if top is not None:
                _inset(img, painter.paint(frame.poses, None, top))
            strip = caption_strip(frame.caption.text(view.total, view.captions), img.width, img.height)
            img.paste(strip, (0, img.height - strip.height))
            out.append(np.asarray(img))
        return out

    def close(self) -> None:
        """Release every replay scene's physics client."""
        for scene in self._scenes.values():
            close_quietly(scene)
        self._scenes.clear()


def _inset(img: Image.Image, small: Image.Image) -> None:
    """Paste ``small`` in the top right corner of ``img`` with a thin dark frame."""
    x = img.width - small.width - 4
    ImageDraw.Draw(img).rectangle((x - 2, 2, img.width - 2, small.height + 6), fill=(60, 60, 60))
    img.paste(small, (x, 4))


_WORKER_RENDERER: ReplayRenderer | None = None  # the one renderer of a rendering worker process


def _init_render_worker(renderer: str) -> None:
    global _WORKER_RENDERER
    _WORKER_RENDERER = ReplayRenderer(renderer)


def _render_in_worker(n: int, config: SimConfig, frames: list[Frame], view: View) -> list[np.ndarray]:
    assert _WORKER_RENDERER is not None, "rendering worker started without _init_render_worker"
    return _WORKER_RENDERER.render(n, config, frames, view)


def _chunks(frames: list[Frame], size: int) -> list[list[Frame]]:
    return [frames[i:i + size] for i in range(0, len(frames), size)]


def _open_writer(path: Path, fps: int, suffix: str) -> FfmpegWriter | GifWriter:
    """The writer of ``path`` in the format of ``suffix`` (.mp4: ffmpeg's libx264, .gif: Pillow)."""
    return FfmpegWriter(path, fps) if suffix == ".mp4" else GifWriter(path, fps)


def write_video(recording: Recording, path: str | os.PathLike, width: int = 640, height: int = 480,
                fps: int | None = None, workers: int | None = None, camera: Camera | None = None,
                progress: bool = True, renderer: str = "auto", top: bool = True) -> Path:
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
        camera: the main view (default: :func:`~csql_sim.sim.framing.goal_camera` of the first and last frames).
        progress: show a tqdm bar on stderr.
        renderer: ``"flat"``, ``"tiny"``, ``"egl"`` or ``"auto"`` (:func:`~csql_sim.sim.renderer.resolve_renderer`).
        top: inset the top view (:func:`~csql_sim.sim.framing.top_camera`) in the top right corner.

    Returns:
        The path written.
    """
    fps = fps or recording.fps
    out = check_video_options(path, width, height, fps)
    renderer = resolve_renderer(renderer)
    if not recording.frames:
        raise VideoError("the recording has no frames")
    view = video_view(recording, width, height, camera, top)
    # the bar counts the frames of the file: the recorded ones and the final hold
    bar = tqdm(total=video_frame_count(recording, fps), desc=f"render {out.name}", unit="frame",
               disable=not progress, delay=PROGRESS_DELAY)
    rendered = _rendered_chunks(recording, view, workers, renderer)
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


def video_view(recording: Recording, width: int, height: int, camera: Camera | None = None,
               top: bool = True) -> View:
    """The :class:`View` of a recording's video: the goal camera (unless ``camera``), the top view, the names."""
    first, last = recording.frames[0].poses, recording.frames[-1].poses
    if camera is None:
        between = [f.poses for f in recording.frames[::FRAMING_STRIDE]]
        camera = goal_camera(first, last, recording.config, width, height, between)
    inset = top_camera(first, last, *inset_size(width, height)) if top else None
    return View(width, height, camera, inset, legend_names(recording.n, recording.names), recording.actions,
                recording.names, recording.arm)


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


def render_frames(recording: Recording, view: View, workers: int | None = None,
                  renderer: str = "flat") -> Iterator[np.ndarray]:
    """The captioned frames of ``recording`` in order (without the final hold), rendered by ``workers`` processes.

    The frames are the same whatever the number of workers (each is drawn from its own
    recorded poses, ``view`` and the renderer alone).
    """
    for chunk in _rendered_chunks(recording, view, workers, resolve_renderer(renderer)):
        yield from chunk


def _rendered_chunks(recording: Recording, view: View, workers: int | None,
                     renderer: str) -> Iterator[list[np.ndarray]]:
    if workers is None and renderer == "flat":  # a process and its replay scene cost about 100 painted frames
        workers = max(1, len(recording.frames) // FRAMES_PER_WORKER)
    cores = worker_count(workers, len(recording.frames))  # at most the cores
    chunks = _chunks(recording.frames, max(1, min(16, len(recording.frames) // (4 * cores) or 1)))
    return _map_chunks(recording, chunks, view, worker_count(workers, len(chunks)), renderer)


def _map_chunks(recording: Recording, chunks: list[list[Frame]], view: View, workers: int,
                renderer: str) -> Iterator[list[np.ndarray]]:
    """Render chunks in order, in ``workers`` processes (or in-process for one worker).

    At most :data:`CHUNKS_IN_FLIGHT` chunks per worker are queued or rendered ahead of the
    encoder (not every frame of the video at once). Futures are never cancelled here: when
    the encoder fails or on Ctrl-C, the pool is stopped (:func:`~csql_sim.infra.workers.stop_pool`).
    """
    n, config = recording.n, recording.config
    if workers <= 1:
        replay = ReplayRenderer(renderer)
        try:
            for c in chunks:
                yield replay.render(n, config, c, view)
        finally:
            replay.close()
        return
    # EGL workers are spawned: a process that has started EGL (llvmpipe's threads) cannot fork safely
    context = multiprocessing.get_context("spawn") if renderer == "egl" else None
    with worker_pool(workers, _init_render_worker, (renderer,), mp_context=context) as pool:
        pending: deque[Future] = deque()
        for chunk in chunks:
            pending.append(pool.submit(_render_in_worker, n, config, chunk, view))
            if len(pending) >= CHUNKS_IN_FLIGHT * workers:
                yield pending.popleft().result()
        while pending:
            yield pending.popleft().result()
