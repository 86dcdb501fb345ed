"""Helpers for the hostile cases of issue 27: run ``csql-sim`` in a subprocess and judge what it did.

Import them in a test module of this folder with ``from hostile_cli import csql, digest, start``
(the folder's conftest puts it on ``sys.path``).
"""

from __future__ import annotations

import hashlib
import os
import resource
import signal
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

MEMORY_LIMIT = 3 << 30
"""The address space a command may take (3 GiB): past it an allocation fails instead of the machine."""


@dataclass(frozen=True)
class Run:
    """What a command did: its exit status and its two streams."""

    returncode: int
    stdout: str
    stderr: str

    def one_line(self, *names: str) -> str:
        """Assert stderr is one line that starts with ``csql-sim`` and names each of ``names``."""
        err = self.stderr
        assert err.count("\n") == 1 and err.startswith("csql-sim"), err
        assert "Traceback" not in err, err
        for name in names:
            assert name in err, err
        return err

    def refused(self, *names: str) -> str:
        """Assert exit status 2 and one error line naming each of ``names``."""
        assert self.returncode == 2, (self.returncode, self.stderr)
        return self.one_line(*names)


def _limits(closed: tuple[int, ...], sigint_default: bool):
    def preexec() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
        if sigint_default:
            signal.signal(signal.SIGINT, signal.SIG_DFL)
        for fd in closed:
            os.close(fd)
    return preexec


def environment(cwd: Path) -> dict[str, str]:
    """The child's environment: its own temporary folder beside ``cwd`` (``<cwd>-tmp``), no bytecode written."""
    tmp = cwd.parent / f"{cwd.name}-tmp"
    tmp.mkdir(exist_ok=True)
    return {**os.environ, "TMPDIR": str(tmp), "PYTHONDONTWRITEBYTECODE": "1", "PYTHONUNBUFFERED": "1"}


def csql(cwd: Path, *argv: object, timeout: float = 240, close: tuple[int, ...] = ()) -> Run:
    """Run ``csql-sim ARGV`` in ``cwd``; ``close`` names the standard streams to close first (1: stdout)."""
    cmd = [sys.executable, "-m", "csql_sim", *map(str, argv)]
    out = subprocess.DEVNULL if 1 in close else subprocess.PIPE
    result = subprocess.run(cmd, cwd=cwd, stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.PIPE, text=True,
                            env=environment(cwd), timeout=timeout, preexec_fn=_limits(close, True))
    return Run(result.returncode, result.stdout or "", result.stderr)


def start(cwd: Path, *argv: object) -> subprocess.Popen:
    """Start ``csql-sim ARGV`` in ``cwd`` (for signal tests), with SIGINT at its default."""
    cmd = [sys.executable, "-m", "csql_sim", *map(str, argv)]
    return subprocess.Popen(cmd, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=environment(cwd), preexec_fn=_limits((), True), start_new_session=True)


def digest(folder: Path) -> dict[str, str]:
    """Every entry under ``folder`` (links not followed) and a hash of each file: to show nothing changed."""
    found = {}
    for path in sorted(folder.rglob("*")):
        rel = str(path.relative_to(folder))
        if path.is_symlink():
            found[rel] = "-> " + os.readlink(path)
        elif path.is_file():
            found[rel] = hashlib.sha256(path.read_bytes()).hexdigest()
        else:
            found[rel] = "dir"
    return found
