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

from csql_sim.cli import main
from csql_sim.core import rulebase_shards as rs

TRAIN = ["train", "--blocks", "4", "--shards", "4", "--workers", "1", "--quiet", "--out"]


@pytest.fixture(scope="module")
def base(tmp_path_factory) -> Path:
    """A complete 4-shard rule base at n = 4, trained once for the module."""
    folder = tmp_path_factory.mktemp("base")
    assert main([*TRAIN, str(folder / "sh")]) == 0
    return folder / "sh"


@pytest.fixture
def stopped(base, work) -> Path:
    """A copy of the base as a stopped run ``sh``: shard 0 missing from the manifest, ``complete`` false."""
    sh = Path(shutil.copytree(base, work / "sh"))
    manifest = rs.read_manifest(sh)
    manifest["files"] = manifest["files"][1:]
    manifest["complete"] = False
    rs.write_manifest(sh, manifest)
    return sh


@pytest.mark.parametrize("report", ["[" * 100_000, '{"runs": ' + "9" * 5000 + "}", "not json"])
def test_shtr_resume_runreport_deep(stopped, base, work, report):
    (stopped / rs.REPORT).write_text(report)
    run = csql(work, "train", "--quiet", "--resume", "--out", "sh", "--workers", 1)
    assert run.returncode == 0, run.stderr
    run.one_line("run-report.json")
    assert rs.read_manifest(stopped) == rs.read_manifest(base)
    runs = json.loads((stopped / rs.REPORT).read_text())["runs"]
    assert [r["shards_trained"] for r in runs] == [[0]]


def test_a_readable_run_report_gets_this_run_appended(stopped, work):
    """The guard sets aside only an unreadable report: a good one keeps its runs and says nothing."""
    run = csql(work, "train", "--quiet", "--resume", "--out", "sh", "--workers", 1)
    assert run.returncode == 0 and run.stderr == "", run.stderr
    runs = json.loads((stopped / rs.REPORT).read_text())["runs"]
    assert [r["shards_trained"] for r in runs] == [[0, 1, 2, 3], [0]]
