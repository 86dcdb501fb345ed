"""Fixtures of the video cases of issue 27: a 3-block problem with its plan, and what may be left after a run."""

from __future__ import annotations

import os
from pathlib import Path

DATA = Path(__file__).resolve().parents[1] / "data" / "problems"
FIXTURES = {"ok3.pddl": DATA / "blocks3-02.pddl", "good.plan": DATA / "blocks3-02.plan"}


def put_fixtures(folder: Path) -> dict[str, bytes]:
    """A 3-block problem (``ok3.pddl``) and an IPC plan that solves it (``good.plan``) in ``folder``; their bytes."""
    for name, source in FIXTURES.items():
        (folder / name).write_bytes(source.read_bytes())
    return {name: (folder / name).read_bytes() for name in FIXTURES}


def only_fixtures_left(folder: Path, fixtures: dict[str, bytes]) -> None:
    """Assert ``folder`` holds the fixtures, unchanged, and nothing else; the command's temporary folder is empty."""
    assert sorted(os.listdir(folder)) == sorted(fixtures)
    assert os.listdir(folder.parent / f"{folder.name}-tmp") == []
    assert {name: (folder / name).read_bytes() for name in fixtures} == fixtures
