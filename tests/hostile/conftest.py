"""Shared fixtures for the hostile cases of issue 27 (``../shared/hostile-cases-2026-11-27.md``).

Each test in this folder reproduces one case of the sweep by its name (``tl-stdout-closed``,
``x-problems-fifo-named-pddl``, ...) and asserts our behaviour: the exit status, one stderr
line naming what is wrong, nothing written or replaced. The files are grouped by the class
of the issue: ``test_clobber_*`` (1, files written outside the outputs), ``test_hangs_*``
(2, hangs and unbounded memory), ``test_tracebacks_*`` (3), ``test_signals_*`` (4),
``test_leftovers_*`` (5) and ``test_ignored_*`` (6, silently wrong or ignored).

The command runs in a subprocess (``python -m csql_sim``) in a scratch folder, with a
timeout and a memory limit, so a hang or a leak fails the test instead of the suite.

Helpers live in ``hostile_cli.py`` beside this file: ``from hostile_cli import csql, digest, start``
(this conftest puts the folder on ``sys.path``).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

@pytest.fixture
def work(tmp_path: Path) -> Path:
    """The scratch folder a command runs in."""
    folder = tmp_path / "work"
    folder.mkdir()
    return folder


@pytest.fixture
def tiny_fs(tmp_path: Path):
    """A 64 KiB file system (tmpfs), for the full-disk cases; skipped where mounting is not allowed."""
    mount = tmp_path / "tiny"
    mount.mkdir()
    if os.geteuid() != 0 or shutil.which("mount") is None:
        pytest.skip("mounting a 64 KiB tmpfs needs root")
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(mount)], capture_output=True)
    if done.returncode != 0:
        pytest.skip("cannot mount a tmpfs here")
    try:
        yield mount
    finally:
        subprocess.run(["umount", "-l", str(mount)], capture_output=True)


@pytest.fixture(scope="session")
def shard_base(tmp_path_factory) -> Path:
    """A complete 4-shard rule base at n = 4, trained once for the whole session (copy it before changing it)."""
    from csql_sim.cli import main

    folder = tmp_path_factory.mktemp("base")
    assert main(["train", "--blocks", "4", "--shards", "4", "--workers", "1", "--quiet", "--out",
                 str(folder / "sh")]) == 0
    return folder / "sh"


@pytest.fixture
def sh(shard_base: Path, work: Path) -> Path:
    """A copy of the 4-shard base in the scratch folder, as ``sh``."""
    return Path(shutil.copytree(shard_base, work / "sh"))
