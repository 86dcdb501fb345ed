"""``evaluate --problems DIR`` with a ``*.pddl`` that is no regular file (issue 27, class 3).

Each ``*.pddl`` of the folder was opened with ``Path.read_text`` to tell problems from
domains: a folder named ``sub.pddl`` or a dangling link gave a traceback, a fifo hung, a
link to ``/dev/zero`` filled the memory. The folder's files are now read with the guarded
reader (regular files only, size-capped); one that cannot be read is a failed row naming
it, and the folder's other problems still run (exit 1, as for a refused plan).
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from pathlib import Path

from hostile_cli import csql

DATA = Path(__file__).resolve().parents[1] / "data" / "problems"
WITHIN = 60
"""Seconds the command may take: one 3-block episode (the fifo used to hang for ever)."""


def run_folder(work: Path, name: str, make: Callable[[Path], None]) -> None:
    """``evaluate --problems probs --planner bfs`` on a good problem and ``name`` made by ``make``: judge it."""
    probs = work / "probs"
    probs.mkdir()
    (probs / "ok3.pddl").write_bytes((DATA / "blocks3-02.pddl").read_bytes())
    make(probs / name)
    run = csql(work, "evaluate", "--problems", "probs", "--planner", "bfs", "--quiet", "--json", timeout=WITHIN)
    assert "Traceback" not in run.stderr and run.stderr == "", run.stderr
    assert run.returncode == 1, (run.returncode, run.stderr)  # a failed row: not every problem reached
    rows = {r["problem"]: r for r in json.loads(run.stdout)["runs"]}
    assert set(rows) == {"ok3.pddl", name}
    assert rows["ok3.pddl"]["reached"]  # the good problem still ran
    bad = rows[name]
    assert not bad["reached"] and bad["actions"] == 0 and os.path.join("probs", name) in bad["reason"], bad


def test_x_problems_subdir_named_pddl(work: Path) -> None:
    run_folder(work, "sub.pddl", lambda p: p.mkdir())


def test_x_problems_fifo_named_pddl(work: Path) -> None:
    run_folder(work, "fifo.pddl", os.mkfifo)


def test_x_problems_devzero_link(work: Path) -> None:
    run_folder(work, "zero.pddl", lambda p: p.symlink_to("/dev/zero"))


def test_x_problems_dangling_link(work: Path) -> None:
    run_folder(work, "gone.pddl", lambda p: p.symlink_to(p.parent / "no-such-file"))


def test_an_unreadable_problem_needs_no_plan(work: Path) -> None:
    """With ``--plans``, a problem that cannot be read is a failed row too, not a missing plan (exit 2)."""
    probs = work / "probs"
    probs.mkdir()
    for name in ("blocks3-02.pddl", "blocks3-02.plan"):
        (probs / name).write_bytes((DATA / name).read_bytes())
    os.mkfifo(probs / "fifo.pddl")
    run = csql(work, "evaluate", "--problems", "probs", "--plans", "probs", "--quiet", "--json", timeout=WITHIN)
    assert run.returncode == 1 and run.stderr == "", run.stderr
    rows = {r["problem"]: r for r in json.loads(run.stdout)["runs"]}
    assert rows["blocks3-02.pddl"]["reached"] and not rows["fifo.pddl"]["reached"]
    assert rows["fifo.pddl"]["plan"] is None
