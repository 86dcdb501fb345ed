"""Video encoders that fail with one line: ffmpeg fed over a pipe with timeouts (.mp4), Pillow (.gif).

imageio's writers failed badly on a full disk: ffmpeg's own messages went straight to our
stderr (8 lines), a write to an ffmpeg that had stopped reading frames without exiting
blocked for ever, and Pillow's GIF encoder, run from imageio's finalizers, printed
"Exception ignored" tracebacks. These writers own their process and file instead:

* :class:`FfmpegWriter` starts ffmpeg in a session of its own (a Ctrl-C reaches us only),
  captures its messages, writes each frame with a deadline (:data:`STALL_SECONDS` without
  a byte taken is a stuck encoder) and gives it :data:`FINISH_SECONDS` to end the file;
  on any failure, KeyboardInterrupt included, ffmpeg is killed and reaped.
* :class:`GifWriter` keeps the frames and encodes them into a file it opens and closes itself.

Both raise :class:`EncoderError` (or OSError) with a short reason; the caller names the file.
"""

from __future__ import annotations

import os
import re
import selectors
import signal
import subprocess
import threading
import time
from pathlib import Path
from types import TracebackType

import numpy as np
from PIL import Image

from csql_sim.infra.errors import CsqlError

STALL_SECONDS = 60.0
"""An encoder that takes no byte of a frame for this long is stuck: it is killed."""
FINISH_SECONDS = 60.0
"""How long ffmpeg may take to finish the file once every frame is sent."""
EXIT_SECONDS = 5.0
"""How long an ffmpeg that closed its input may take to exit (and say why) before it is killed."""
LOG_BYTES = 8192
"""How much of ffmpeg's last messages is kept for the error line."""
MP4_CRF = 15  # libx264 quality (imageio's quality=7)
_LOG_PREFIX = re.compile(r"^(\[[^\]]*\]\s*)+")  # ffmpeg's "[out#0/mp4 @ 0x55...] " before a message


class EncoderError(CsqlError):
    """The encoder failed, stopped or got frames it cannot encode; the message says why, not which file."""


def ffmpeg_executable() -> str:
    """The ffmpeg that imageio-ffmpeg ships (or ``IMAGEIO_FFMPEG_EXE``)."""
    import imageio_ffmpeg

    try:
        return imageio_ffmpeg.get_ffmpeg_exe()
    except RuntimeError as exc:
        raise EncoderError(f"no ffmpeg to encode .mp4 ({' '.join(str(exc).split())})") from None


def _frame_bytes(rgb: np.ndarray) -> memoryview:
    frame = np.ascontiguousarray(rgb, dtype=np.uint8)
    if frame.ndim != 3 or frame.shape[2] != 3:
        raise EncoderError(f"frames must be height x width x 3 RGB, got shape {frame.shape}")
    return memoryview(frame).cast("B")


class FfmpegWriter:
    """An H.264 .mp4 written by an ffmpeg process fed raw RGB frames on its stdin.

    Use as a context manager: on a normal exit the file is finished (:meth:`close`), on an
    exception ffmpeg is killed (:meth:`abort`). The frame size is that of the first frame.

    Args:
        path: the file to write.
        fps: playback frame rate.
        stall: seconds without progress after which a write fails (default :data:`STALL_SECONDS`).
        finish: seconds ffmpeg may take to end the file (default :data:`FINISH_SECONDS`).
    """

    def __init__(self, path: str | os.PathLike, fps: int, stall: float | None = None,
                 finish: float | None = None) -> None:
        self.path, self.fps = Path(path), fps
        self.stall = STALL_SECONDS if stall is None else stall
        self.finish = FINISH_SECONDS if finish is None else finish
        self._process: subprocess.Popen | None = None
        self._shape: tuple[int, ...] | None = None
        self._log = bytearray()
        self._reader: threading.Thread | None = None

    def __enter__(self) -> FfmpegWriter:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        if kind is None:
            self.close()
        else:
            self.abort()

    def _start(self, shape: tuple[int, ...]) -> None:
        """Start ffmpeg for frames of ``shape`` and the thread that keeps its messages."""
        height, width = shape[:2]
        cmd = [ffmpeg_executable(), "-y", "-v", "error", "-f", "rawvideo", "-vcodec", "rawvideo",
               "-s", f"{width}x{height}", "-pix_fmt", "rgb24", "-r", str(self.fps), "-i", "-", "-an",
               "-vcodec", "libx264", "-pix_fmt", "yuv420p", "-crf", str(MP4_CRF), "-preset", "ultrafast",
               "-f", "mp4", str(self.path)]
        self._process = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                                         stderr=subprocess.PIPE, bufsize=0, start_new_session=True)
        os.set_blocking(self._process.stdin.fileno(), False)
        self._reader = threading.Thread(target=self._read_log, args=(self._process.stderr,),
                                        name="csql-sim-ffmpeg-log", daemon=True)
        self._reader.start()

    def _read_log(self, stream) -> None:  # noqa: ANN001 - the process's stderr pipe
        """Keep the last :data:`LOG_BYTES` of ffmpeg's messages (until it closes its stderr)."""
        try:
            while chunk := stream.read(4096):
                self._log += chunk
                del self._log[:-LOG_BYTES]
        except (OSError, ValueError):
            pass

    def append_data(self, rgb: np.ndarray) -> None:
        """Encode one frame (height x width x 3, uint8; every frame the size of the first)."""
        data = _frame_bytes(rgb)
        if self._process is None:
            self._shape = tuple(np.shape(rgb))
            self._start(self._shape)
        elif tuple(np.shape(rgb)) != self._shape:
            raise EncoderError(f"frame of shape {np.shape(rgb)} after frames of shape {self._shape}")
        self._send(data)

    def _send(self, data: memoryview) -> None:
        """Write ``data`` to ffmpeg; a failure if it exits or takes nothing for ``stall`` seconds."""
        assert self._process is not None and self._process.stdin is not None
        fd = self._process.stdin.fileno()
        with selectors.DefaultSelector() as selector:
            selector.register(fd, selectors.EVENT_WRITE)
            deadline = time.monotonic() + self.stall
            while data:
                if not selector.select(max(0.0, deadline - time.monotonic())):
                    if time.monotonic() >= deadline:
                        raise self._failure(f"the encoder (ffmpeg) took no frame data for {self.stall:g} s")
                    continue
                try:
                    sent = os.write(fd, data)
                except BlockingIOError:
                    continue
                except (BrokenPipeError, ConnectionResetError):
                    raise self._failure("the encoder (ffmpeg) stopped", wait=EXIT_SECONDS) from None
                data = data[sent:]
                deadline = time.monotonic() + self.stall

    def close(self) -> None:
        """Finish the file: end ffmpeg's input and wait for it; a failure unless it exits with status 0."""
        if self._process is None:
            raise EncoderError("no frames to encode")
        try:
            self._process.stdin.close()
            try:
                self._process.wait(self.finish)
            except subprocess.TimeoutExpired:
                raise self._failure(f"the encoder (ffmpeg) did not finish within {self.finish:g} s") from None
            if self._process.returncode != 0:
                raise self._failure("the encoder (ffmpeg) failed")
        finally:
            self.abort()

    def abort(self) -> None:
        """Kill ffmpeg if it still runs, reap it and close its pipes (safe to call twice)."""
        process = self._process
        if process is None:
            return
        if process.poll() is None:
            try:
                process.kill()
            except OSError:
                pass
        try:
            process.wait(EXIT_SECONDS)
        except subprocess.TimeoutExpired:  # killed but not yet gone (a stuck disk): not ours to wait for
            pass
        if self._reader is not None:
            self._reader.join(1.0)  # ffmpeg is gone: its stderr ends
        for stream in (process.stdin, None if self._reader and self._reader.is_alive() else process.stderr):
            try:
                if stream is not None:
                    stream.close()
            except OSError:
                pass

    def _failure(self, what: str, wait: float = 0.0) -> EncoderError:
        """An EncoderError: ``what`` and ffmpeg's last message (or how it ended); ffmpeg is reaped first.

        ``wait``: seconds ffmpeg may take to exit on its own (and say why) before it is killed.
        """
        assert self._process is not None
        try:
            self._process.wait(wait)
        except subprocess.TimeoutExpired:
            pass
        self.abort()
        code = self._process.returncode
        said = last_message(bytes(self._log))
        if said:
            return EncoderError(f"{what}: {said}")
        if code is not None and code < 0 and code != -signal.SIGKILL:
            return EncoderError(f"{what}: {signal.strsignal(-code) or f'signal {-code}'}")
        return EncoderError(what if code in (None, 0, -signal.SIGKILL) else f"{what} with status {code}")


def last_message(log: bytes) -> str:
    """The last message line ffmpeg wrote in ``log``, without its ``[component @ address]`` prefix; or empty."""
    lines = [_LOG_PREFIX.sub("", line).strip() for line in log.decode("utf-8", "replace").splitlines()]
    lines = [line for line in lines if line and not line.startswith("Last message repeated")]
    return lines[-1] if lines else ""


class GifWriter:
    """An animated GIF: frames are kept, then encoded by Pillow into a file opened and closed here.

    Use as a context manager: the file is written on a normal exit only; errors (a full
    disk) surface as OSError from the ``with`` block, never from a finalizer.
    """

    def __init__(self, path: str | os.PathLike, fps: int) -> None:
        self.path, self.fps = Path(path), fps
        self._frames: list[Image.Image] = []

    def __enter__(self) -> GifWriter:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        try:
            if kind is None:
                self.close()
        finally:
            self._frames.clear()

    def append_data(self, rgb: np.ndarray) -> None:
        """Keep one frame (height x width x 3, uint8)."""
        self._frames.append(Image.fromarray(np.ascontiguousarray(rgb, dtype=np.uint8)))

    def close(self) -> None:
        """Encode the frames kept into the file (looping, ``1000 / fps`` ms a frame)."""
        if not self._frames:
            raise EncoderError("no frames to encode")
        first, *rest = self._frames
        with open(self.path, "wb") as fh:
            first.save(fh, format="GIF", save_all=True, append_images=rest, duration=1000.0 / self.fps, loop=0)
