"""Class 3 of issue 27: hostile JSON is one line and exit 2, never a traceback.

Before the fix every JSON input went straight to ``json.loads``: a file nested 100,000
levels deep (a lifted file's ``meta``, a sharded base's ``manifest.json``, a shard's header
line) raised RecursionError, and an integer of 5,000 digits (a lifted Q-classifier's
``experience=``) Python's 4,300-digit ValueError. Now every JSON input goes through
:func:`csql_sim.infra.files.load_json` (nesting bounded by a linear scan before the parser
runs, integer digits bounded) and integers read from text fields are bounded too.
"""

from __future__ import annotations

import hashlib
import json
import re
from pathlib import Path

import pytest
from hostile_cli import csql, digest

from csql_sim.core.files import rulebase_shards as rs

SHIPPED = Path(__file__).resolve().parents[2] / "assets" / "rules" / "lifted.json"
DEEP = "[" * 100_000


def _lifted(work: Path, name: str, meta: str | None = None, experience: str | None = None) -> str:
    """The shipped lifted Q-classifiers with ``meta`` spliced in as raw JSON, or every ``experience=`` replaced."""
    doc = json.loads(SHIPPED.read_text(encoding="utf-8"))
    if experience is not None:
        doc["classifiers"] = [re.sub(r"experience=\d+", f"experience={experience}", c) for c in doc["classifiers"]]
    text = json.dumps(doc if meta is None else {**doc, "meta": "META"}, indent=2)
    (work / name).write_text(text if meta is None else text.replace('"META"', meta), encoding="utf-8")
    return name


PLAN_8 = ("plan", "--blocks", 8, "--start", "ABCDEFGH", "--goal", "HGFEDCBA", "--rules")


def test_lj_L_exp_5000digits(work):
    name = _lifted(work, "L_exp_5000digits.json", experience="9" * 5000)
    csql(work, *PLAN_8, name).refused(name, "experience")


def test_lj_L_deep_meta(work):
    name = _lifted(work, "L_deep_meta.json", meta=DEEP)
    csql(work, *PLAN_8, name).refused(name)


def test_lj_L_deep_meta_obj(work):
    name = _lifted(work, "L_deep_meta_obj.json", meta='{"a": ' * 100_000)
    csql(work, *PLAN_8, name).refused(name)


def test_lj_render_lifted_bad(work):
    name = _lifted(work, "L_exp_5000digits.json", experience="9" * 5000)
    run = csql(work, "render", "--start", "ABCDEFGH", "--goal", "HGFEDCBA", "--rules", name, "--out", "v.gif",
               "--width", 32, "--height", 32)
    run.refused(name)
    assert not (work / "v.gif").exists()


def test_a_lifted_file_the_tool_wrote_still_plans(work):
    """The bounds refuse only what the tool never writes: the shipped file (its experience, its meta) plans."""
    name = _lifted(work, "ok.json", meta=json.dumps(json.loads(SHIPPED.read_text(encoding="utf-8"))["meta"]),
                   experience="9" * 18)
    run = csql(work, *PLAN_8, name)
    assert run.returncode == 0 and "Traceback" not in run.stderr, run.stderr


@pytest.mark.parametrize("case, argv", [
    ("sh-plan-deep-manifest", ["plan", "--rules", "sh", "--start", "ABCD", "--goal", "DCBA"]),
    ("sh-show-deep-manifest", ["show", "--rules", "sh", "--start", "ABCD", "--goal", "DCBA"]),
    ("sh-eval-deep-manifest", ["evaluate", "--rules", "sh", "--blocks", "4", "--pairs", "2", "--quiet"]),
    ("sh-pairs-deep-manifest", ["plan", "--rules", "sh", "--pairs", "50"]),
    ("shtr-resume-manifest-deep", ["train", "--quiet", "--resume", "--out", "sh"]),
])
def test_sh_deep_manifest(sh, work, case, argv):
    (sh / rs.MANIFEST).write_text(DEEP)
    before = digest(work)
    csql(work, *argv).refused("manifest.json")
    assert digest(work) == before


def test_z_shard_header_deep(sh, work):
    """Every shard's header line is 4,000 ``[`` (the manifest's SHA-256 updated to match)."""
    manifest = rs.read_manifest(sh)
    for entry in manifest["files"]:
        path = sh / entry["file"]
        rest = path.read_bytes()[len(rs.MAGIC):].split(b"\n", 1)[1]
        path.write_bytes(rs.MAGIC + b"[" * 4000 + b"\n" + rest)
        entry["sha256"] = hashlib.sha256(path.read_bytes()).hexdigest()
    rs.write_manifest(sh, manifest)
    csql(work, "plan", "--rules", "sh", "--pairs", 100).refused("sh/shard-0000", ".bin")


def _drop_first_shard(sh: Path) -> None:
    """Make ``sh`` a stopped run: shard 0 missing from the manifest, ``complete`` false."""
    manifest = rs.read_manifest(sh)
    manifest["files"] = manifest["files"][1:]
    manifest["complete"] = False
    rs.write_manifest(sh, manifest)


def test_shtr_resume_shard_is_dir(sh, work):
    _drop_first_shard(sh)
    (sh / "shard-00000.bin").unlink()
    (sh / "shard-00000.bin").mkdir()
    before = digest(work)
    csql(work, "train", "--quiet", "--resume", "--out", "sh", "--workers", 1).refused("shard-00000.bin")
    assert digest(work) == before
