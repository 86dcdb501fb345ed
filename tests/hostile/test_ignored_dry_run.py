"""Class 6 of issue 27 (silently wrong or ignored): `--dry-run` runs the run's checks; `--plan-out` with `--pairs`.

Cases ``est-blocks6-npz`` and ``est-blocks6-ltql``: the estimate said the job fits (exit 0)
where the real run refuses it; ``plan-planout-pairs``: ``--plan-out`` was silently ignored
with ``--pairs``.
"""

import pytest
from hostile_cli import csql


@pytest.mark.parametrize("case, extra", [("est-blocks6-npz", []), ("est-blocks6-ltql", ["--method", "lt-ql"])])
def test_a_dry_run_refuses_what_the_run_refuses(work, case, extra):
    dry = csql(work, "train", "--blocks", "6", "--out", "r6.npz", *extra, "--dry-run")
    real = csql(work, "train", "--blocks", "6", "--out", "r6.npz", *extra, "--max-memory", "1G")
    dry.refused("r6.npz" if case == "est-blocks6-npz" else "cs-ql")
    real.refused()
    assert dry.stderr == real.stderr
    assert list(work.iterdir()) == []


def test_a_dry_run_of_a_job_that_fits_says_so(work):
    run = csql(work, "train", "--blocks", "6", "--out", "r6", "--dry-run")
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("estimate: cs-ql, 6 blocks")
    assert list(work.iterdir()) == []


@pytest.mark.parametrize("argv", [["--blocks", "8", "--pairs", "3", "--planner", "gn1"], ["--pairs", "3"],
                                  ["--pairs", "all"]])
def test_plan_planout_pairs(work, argv):
    csql(work, "plan", *argv, "--plan-out", "x.plan").refused("--plan-out", "--")
    assert list(work.iterdir()) == []
