"""Class 3 of issue 27: a closed standard output (``>&-``) is one line and exit 2, never a traceback.

Cases ``tl-stdout-closed``, ``plan-stdout-closed``, ``ex-stdout-closed`` and ``io-states-closed``:
before the fix each gave an AttributeError (``sys.stdout`` is None when fd 1 is closed).
The command is refused before any work, so nothing is written: its report could not be
shown.
"""

import shutil
from pathlib import Path

from hostile_cli import csql

PROBLEMS = Path(__file__).parents[1] / "data" / "problems"


def test_plan_stdout_closed(work):
    run = csql(work, "plan", "--start", "CBA", "--goal", "BAC", close=(1,))
    run.refused("standard output")
    assert list(work.iterdir()) == []


def test_io_states_closed(work):
    csql(work, "states", "--blocks", "6", close=(1,)).refused("standard output")


def test_tl_stdout_closed(work):
    run = csql(work, "train-lifted", "--quiet", "--trials", "50", "--sizes", "3", "--goals", "3", "--out", "l.json",
               close=(1,))
    run.refused("standard output")
    assert list(work.iterdir()) == []  # refused before any work


def test_ex_stdout_closed(work):
    shutil.copy(PROBLEMS / "blocks3-01.pddl", work / "ok3.pddl")
    shutil.copy(PROBLEMS / "blocks3-01.plan", work / "good.plan")
    run = csql(work, "execute", "--quiet", "--problem", "ok3.pddl", "--plan", "good.plan", close=(1,))
    run.refused("standard output")


def test_a_closed_stderr_keeps_the_exit_status_and_writes_no_file_in_its_place(work):
    run = csql(work, "plan", "--start", "CBx", "--goal", "BAC", close=(2,))
    assert run.returncode == 2
    assert sorted(p.name for p in work.iterdir()) == []

