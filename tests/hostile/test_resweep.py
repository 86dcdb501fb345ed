"""Cases a second hostile sweep found after issue 27's fixes (543 cases, 31 failures in about 10 bugs).

Each test is one bug of the re-sweep: an unguarded ``.npz`` reader, a sharded run refused by
an unreachable Ray cluster that left its folder behind, ``--dry-run`` that did not read
``--params``, a model of another kind replaced without ``--overwrite``.
"""

import os

import pytest
from hostile_cli import csql, digest


@pytest.mark.parametrize("make", ["fifo", "devzero"])
def test_an_npz_rule_file_that_is_no_file_is_refused_without_reading(work, make):
    target = work / "R.npz"
    if make == "fifo":
        os.mkfifo(target)
    else:
        os.symlink("/dev/zero", target)
    run = csql(work, "plan", "--start", "CBA", "--goal", "BAC", "--rules", "R.npz", timeout=60)
    run.refused("R.npz")


def test_a_sharded_run_that_cannot_reach_ray_leaves_nothing(work):
    pytest.importorskip("ray")
    run = csql(work, "train", "--quiet", "--blocks", "4", "--shards", "4", "--backend", "ray", "--address",
               "127.0.0.1:1", "--out", "s2", timeout=120)
    run.refused("127.0.0.1:1")
    assert list(work.iterdir()) == []


def test_a_dry_run_reads_the_parameter_file_as_the_run_does(work):
    (work / "P.yaml").write_text("[" * 100_000)
    before = digest(work)
    for extra in (["--dry-run"], []):
        run = csql(work, "train", "--quiet", "--blocks", "3", "--params", "P.yaml", "--out", "r.npz", *extra)
        run.refused("P.yaml")
    assert digest(work) == before


def test_a_model_of_another_kind_is_replaced_only_with_overwrite(work):
    assert csql(work, "train-lifted", "--quiet", "--trials", "20", "--sizes", "3", "--goals", "2",
                "--out", "l.json").returncode == 0
    before = digest(work)
    csql(work, "train", "--quiet", "--trials", "20", "--out", "l.json").refused("l.json", "--overwrite")
    csql(work, "train", "--quiet", "--trials", "20", "--out", "l.json", "--dry-run").refused("l.json")
    assert digest(work) == before
