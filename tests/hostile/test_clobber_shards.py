"""Class 1 of issue 27: a sharded rule base's directory is written without following links.

Cases ``shtr-resume-symlink-victim`` and ``shtr-overwrite-symlinked-shard``: a link named
``shard-00000.bin`` pointing outside the directory was written through (the victim file
replaced by a shard). Case ``shtr-resume-manifest-tampered-trials``: ``--resume`` adopted
``"trials": "lots"`` from the manifest, trained, failed and rewrote the directory. Now a
link or folder in place of one of the directory's files is refused before any work, the
files are written with ``follow_links=False``, and every manifest field is checked.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hostile_cli import csql, digest

from csql_sim.core.files import rulebase_shards as rs

TRAIN = ["train", "--blocks", "4", "--shards", "4", "--workers", "1", "--quiet", "--out"]
VICTIM = b"precious: not a shard\n"


def _drop_first_shard(sh: Path) -> None:
    """Make ``sh`` a stopped run: shard 0 missing from the manifest, ``complete`` false."""
    manifest = rs.read_manifest(sh)
    manifest["files"] = manifest["files"][1:]
    manifest["complete"] = False
    rs.write_manifest(sh, manifest)


def _link_first_shard(sh: Path, work: Path) -> Path:
    victim = work / "victim.txt"
    victim.write_bytes(VICTIM)
    (sh / "shard-00000.bin").unlink()
    (sh / "shard-00000.bin").symlink_to("../victim.txt")
    return victim


def test_shtr_resume_symlink_victim(sh, work):
    _drop_first_shard(sh)
    victim = _link_first_shard(sh, work)
    before = digest(work)
    csql(work, "train", "--quiet", "--resume", "--out", "sh", "--workers", 1).refused("shard-00000.bin")
    assert victim.read_bytes() == VICTIM and digest(work) == before


def test_shtr_overwrite_symlinked_shard(sh, work):
    victim = _link_first_shard(sh, work)
    before = digest(work)
    csql(work, *TRAIN, "sh", "--overwrite").refused("shard-00000.bin")
    assert victim.read_bytes() == VICTIM and digest(work) == before


def test_shtr_resume_manifest_tampered_trials(sh, work):
    _drop_first_shard(sh)
    manifest = json.loads((sh / rs.MANIFEST).read_text())
    manifest["trials"] = "lots"
    (sh / rs.MANIFEST).write_text(json.dumps(manifest))
    before = digest(work)
    csql(work, "train", "--quiet", "--resume", "--out", "sh").refused("manifest.json", "trials")
    assert digest(work) == before


@pytest.mark.parametrize("field, value", [
    ("seed", -1), ("blocks", 9), ("shards", 0), ("count", 7), ("method", "lt-ql"), ("params", []),
    ("params", {"gamma": "high"}), ("complete", True), ("files", {}), ("files", [{"shard": 0}]),
])
def test_every_field_a_resume_reads_is_checked_first(sh, work, field, value):
    """Each field of the wrong type or value is named in one line before any work, the directory untouched."""
    _drop_first_shard(sh)
    manifest = json.loads((sh / rs.MANIFEST).read_text())
    manifest[field] = value
    (sh / rs.MANIFEST).write_text(json.dumps(manifest))
    before = digest(work)
    csql(work, "train", "--quiet", "--resume", "--out", "sh").refused("manifest.json", field)
    assert digest(work) == before


def test_a_stopped_run_still_resumes_to_the_complete_base(sh, shard_base, work):
    """The checks refuse only what the tool never writes: a stopped run resumes to the same bytes."""
    _drop_first_shard(sh)
    (sh / "shard-00000.bin").unlink()
    run = csql(work, "train", "--quiet", "--resume", "--out", "sh", "--workers", 1)
    assert run.returncode == 0, run.stderr
    for name in (rs.MANIFEST, *(rs.shard_name(k) for k in range(4))):
        assert (sh / name).read_bytes() == (shard_base / name).read_bytes(), name
