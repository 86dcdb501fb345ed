"""Class 2 of issue 49: work bounded before it starts, and rows printed as they finish.

``problems --count`` had no bound, drew every problem in memory before writing one, and
compared every pair of outputs (``--count 2000``: six minutes before the first file;
``--count 10^9`` grew without end). The count is now bounded before anything is drawn
(10,000 problems in all), problems are drawn and written one at a time, and the output
check is linear. ``plan --problems`` printed nothing before its last problem; each row is
now printed when it is done, so a stopped run has printed the rows done so far.
"""

from __future__ import annotations

import json
import signal
import time
from pathlib import Path

import pytest
from hostile_cli import csql, digest, start
from sweep4 import tower_problem


@pytest.mark.parametrize(("blocks", "count"), [(5, 1_000_000_000), (2, 100_000)])
def test_gen_count_is_refused_before_any_draw(work: Path, blocks: int, count: int) -> None:
    """gen-count-1e9, gen-count-1e5: refused at once (the timeout is far below what drawing would take)."""
    run = csql(work, "problems", "--blocks", blocks, "--count", count, "--out", "o", timeout=30)
    run.refused("10,000", f"{count:,}")
    assert digest(work) == {}


def test_gen_count_scaling_writes_many_problems_promptly(work: Path) -> None:
    """gen-count-scaling: 1,000 problems are all written (the output check was quadratic)."""
    run = csql(work, "problems", "--blocks", 2, "--count", 1000, "--out", "o", timeout=120)
    assert run.returncode == 0 and run.stderr == "", run.stderr
    assert len(list((work / "o").glob("tall-towers-2-*.pddl"))) == 1000 and (work / "o" / "domain.pddl").is_file()


def test_pd_rows_stream_so_a_stopped_run_leaves_the_rows_done(work: Path) -> None:
    """pd-10000: with --json to stdout the rows done are printed before the run ends; stopped, they stay."""
    (work / "pr").mkdir()
    for k in range(3):
        tower_problem(work / "pr", f"a{k}.pddl", 4)
    tower_problem(work / "pr", "z-tall.pddl", 1500)  # long enough to be stopped while planning it
    proc = start(work, "plan", "--problems", "pr", "--planner", "gn1", "--optimum-budget", 0, "--json")
    rows, began = [], time.monotonic()
    while len(rows) < 3 and time.monotonic() - began < 120:
        line = proc.stdout.readline()
        if not line:
            break
        row = line.strip().strip(",")  # a row a line, the separating comma at its end
        if row.startswith('{"problem"'):
            rows.append(json.loads(row))
    proc.send_signal(signal.SIGINT)
    proc.communicate(timeout=30)
    assert [Path(r["problem"]).name for r in rows] == ["a0.pddl", "a1.pddl", "a2.pddl"]
    assert all(r["solved"] and r["cost"] == 8 for r in rows)
