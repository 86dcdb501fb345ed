"""Fixtures for the CLI tests: a folder nobody can write in, even root."""

import os
import shutil
import subprocess

import pytest


@pytest.fixture
def read_only_dir(tmp_path):
    """A read-only folder: mode 0555, and immutable (chattr +i) when running as root."""
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    immutable = False
    if os.geteuid() == 0:
        if shutil.which("chattr") is None or subprocess.run(["chattr", "+i", str(folder)],
                                                           capture_output=True).returncode != 0:
            pytest.skip("running as root without chattr +i: no folder is read-only")
        immutable = True
    try:
        yield folder
    finally:
        if immutable:
            subprocess.run(["chattr", "-i", str(folder)], check=True)
        folder.chmod(0o755)
