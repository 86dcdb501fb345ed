"""Off-screen rendering of recorded episodes into captioned .mp4 or .gif videos.

Poses are recorded during simulation (see :mod:`csql_sim.sim.video.recording`); frames are
drawn afterwards (:mod:`csql_sim.sim.video.frames`: by the flat painter, or by the TinyRenderer
or pybullet's EGL plugin in replay scenes, :mod:`csql_sim.sim.video.renderer`), in this process
or in worker processes, from the recorded poses alone: the frames are the same whatever
the number of workers. The view is framed from the recording
(:mod:`csql_sim.sim.video.framing`). The frames are encoded by the writers of
:mod:`csql_sim.sim.video.encoders` (ffmpeg with timeouts, Pillow), whose failures are one line.
"""

from __future__ import annotations

import multiprocessing
import os
from collections import deque
from collections.abc import Iterator
from concurrent.futures import Future
from dataclasses import dataclass
from pathlib import Path

import imageio.v2 as imageio
import numpy as np
from tqdm import tqdm

from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import atomic_output, check_output_file
from csql_sim.infra.workers import worker_count, worker_pool
from csql_sim.sim.perception.camera import Camera
from csql_sim.sim.video.encoders import EncoderError, FfmpegWriter, GifWriter
from csql_sim.sim.video.frames import (  # noqa: F401 - caption_image, CAPTION_HEIGHT: used from here by scripts and tests
    CAPTION_HEIGHT,
    ReplayRenderer,
    View,
    caption_image,
    inset_size,
)
from csql_sim.sim.video.framing import goal_camera, top_camera
from csql_sim.sim.video.recording import Frame, Recording
from csql_sim.sim.video.renderer import resolve_renderer
from csql_sim.sim.world.config import SimConfig
from csql_sim.sim.world.legend import legend_names

VIDEO_SUFFIXES = (".mp4", ".gif")
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
        renderer: ``"auto"``, ``"flat"``, ``"tiny"`` or ``"egl"``
            (:func:`~csql_sim.sim.video.renderer.resolve_renderer`).
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
        camera: the main view (default: :func:`~csql_sim.sim.video.framing.goal_camera` of the first and last frames).
        progress: show a tqdm bar on stderr.
        renderer: ``"flat"``, ``"tiny"``, ``"egl"`` or ``"auto"``
            (:func:`~csql_sim.sim.video.renderer.resolve_renderer`).
        top: inset the top view (:func:`~csql_sim.sim.video.framing.top_camera`) in the top right corner.

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
