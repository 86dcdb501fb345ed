"""Class 6 of issue 27: an unreadable run report is said, before work, not a crash after it.

Case ``shtr-resume-runreport-deep``: ``run-report.json`` nested 100,000 levels deep made
``train --resume`` train every missing shard and then die with a RecursionError while
appending its report (exit 1). The reports are not part of the rule base: now the file is
read before work with the guarded JSON reader; an unreadable one is named in one warning
line and replaced by this run's report, and the resumed base is complete.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from hostile_cli import csql

from csql_sim.core.files import rulebase_shards as rs


@pytest.fixture
def stopped(shard_base, work) -> Path:
    """A copy of the base as a stopped run ``sh``: shard 0 missing from the manifest, ``complete`` false."""
    sh = Path(shutil.copytree(shard_base, work / "sh"))
    manifest = rs.read_manifest(sh)
    manifest["files"] = manifest["files"][1:]
    manifest["complete"] = False
    rs.write_manifest(sh, manifest)
    return sh


@pytest.mark.parametrize("report", ["[" * 100_000, '{"runs": ' + "9" * 5000 + "}", "not json"])
def test_shtr_resume_runreport_deep(stopped, shard_base, work, report):
    (stopped / rs.REPORT).write_text(report)
    run = csql(work, "train", "--quiet", "--resume", "--out", "sh", "--workers", 1)
    assert run.returncode == 0, run.stderr
    run.one_line("run-report.json")
    assert rs.read_manifest(stopped) == rs.read_manifest(shard_base)
    runs = json.loads((stopped / rs.REPORT).read_text())["runs"]
    assert [r["shards_trained"] for r in runs] == [[0]]


def test_a_readable_run_report_gets_this_run_appended(stopped, work):
    """The guard sets aside only an unreadable report: a good one keeps its runs and says nothing."""
    run = csql(work, "train", "--quiet", "--resume", "--out", "sh", "--workers", 1)
    assert run.returncode == 0 and run.stderr == "", run.stderr
    runs = json.loads((stopped / rs.REPORT).read_text())["runs"]
    assert [r["shards_trained"] for r in runs] == [[0, 1, 2, 3], [0]]
