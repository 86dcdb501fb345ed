"""Progress bars only on a terminal; the interrupt message on a line of its own."""

import contextlib
import fcntl
import os
import pty
import select
import signal
import struct
import subprocess
import sys
import termios
import time

import pytest


def test_no_progress_bar_or_banner_when_stderr_is_not_a_terminal(tmp_path):
    out = subprocess.run([sys.executable, "-m", "csql_sim", "evaluate", "--pairs", "2", "--workers", "2",
                          "--plot", str(tmp_path / "e.png")], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0
    assert out.stderr == f"wrote {tmp_path / 'e.png'}\n"  # no bar, no "pybullet build time" from the workers
    assert "pybullet" not in out.stdout and out.stdout.startswith("legend: A = red, B = green, C = blue\nepisodes: 2\n")


def _read(fd: int, seconds: float) -> bytes:
    data, end = b"", time.monotonic() + seconds
    while time.monotonic() < end:
        ready, _, _ = select.select([fd], [], [], 0.1)
        if ready:
            try:
                chunk = os.read(fd, 4096)
            except OSError:
                break
            if not chunk:
                break
            data += chunk
    return data


def screen_lines(text: str) -> list[str]:
    """What a terminal shows for ``text``: each line after carriage returns overwrote it."""
    shown = []
    for line in text.replace("\r\n", "\n").split("\n"):
        cells: list[str] = []
        cursor = 0
        for ch in line:
            if ch == "\r":
                cursor = 0
                continue
            cells[cursor:cursor + 1] = [ch]
            cursor += 1
        shown.append("".join(cells).rstrip())
    return shown


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="pty")
@pytest.mark.parametrize(("argv", "bar"), [
    (["train", "--trials", "1000000", "--out", "r.yaml"], b"cs-ql:"),
    (["experiment", "--cycles", "20", "--workers", "2", "--out", "fig"], b"cycles:"),
])
def test_interrupted_is_on_its_own_line_after_a_progress_bar(tmp_path, argv, bar):
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))  # a 100-column terminal
    proc = subprocess.Popen([sys.executable, "-m", "csql_sim", *argv], stdout=subprocess.DEVNULL, stderr=slave,
                            start_new_session=True, cwd=tmp_path)
    os.close(slave)
    seen = b""
    try:
        deadline = time.monotonic() + 60
        while bar not in seen and time.monotonic() < deadline:  # the bar is drawn: stderr is a terminal
            seen += _read(master, 0.5)
        assert bar in seen
        os.killpg(proc.pid, signal.SIGINT)
        assert proc.wait(timeout=30) == 130
        seen += _read(master, 1.0)
    finally:
        os.close(master)
    text = seen.decode(errors="replace")
    assert [line for line in screen_lines(text) if "csql-sim" in line] == ["csql-sim: interrupted"], repr(text[-300:])
    assert "Traceback" not in text and list(tmp_path.iterdir()) == []


def test_an_inherited_ignored_sigint_is_kept_and_sigterm_still_stops(tmp_path):
    """Started with SIGINT ignored (a shell's background job), the CLI keeps ignoring it, as Unix tools do."""
    proc = subprocess.Popen([sys.executable, "-m", "csql_sim", "train", "--trials", "1000000000", "--out", "r.yaml",
                             "--quiet"], cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))
    try:
        time.sleep(4.0)  # into training
        assert proc.poll() is None, proc.communicate()
        proc.send_signal(signal.SIGINT)
        time.sleep(1.5)
        assert proc.poll() is None  # ignored, as inherited
        proc.send_signal(signal.SIGTERM)
        out, err = proc.communicate(timeout=60)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    assert proc.returncode == 143 and err.startswith("csql-sim: terminated") and err.count("\n") == 1, err
    assert os.listdir(tmp_path) == []
