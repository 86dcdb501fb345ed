"""Class 1 of issue 27: a report never replaces a model, even with ``--overwrite``.

Cases ``x-plan-json-over-lifted-model``, ``x-states-json-over-lifted-model``,
``x-evaluate-json-over-lifted-model``, ``x-plan-json-over-lifted-rules`` and
``x-plan-json-over-run-report``: before the fix any ``{"format": "csql-sim ...`` file counted
as a report, so ``--json model.json`` replaced a trained model and exited 0.
"""

import shutil

import pytest
from hostile_cli import csql, digest

from csql_sim.cli import main
from csql_sim.core.classifiers.lifted_rule import BLOCKS_WORLD, dumps_lifted
from csql_sim.infra import formats


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    """A lifted Q-classifier file, a lifted rule file and a 2-shard rule base, made by the tool itself."""
    folder = tmp_path_factory.mktemp("models")
    assert main(["train-lifted", "--quiet", "--trials", "20", "--sizes", "3", "--goals", "2",
                 "--out", str(folder / "model.json")]) == 0
    (folder / "lr.json").write_text(dumps_lifted(BLOCKS_WORLD, {"source": "test"}))
    assert main(["train", "--quiet", "--blocks", "3", "--shards", "2", "--workers", "1",
                 "--out", str(folder / "sh")]) == 0
    return folder


@pytest.fixture
def here(models, work):
    for name in ("model.json", "lr.json"):
        shutil.copy(models / name, work / name)
    shutil.copytree(models / "sh", work / "sh")
    return work


@pytest.mark.parametrize("case, argv, target", [
    ("x-plan-json-over-lifted-model", ["plan", "--start", "CBA", "--goal", "BAC", "--json"], "model.json"),
    ("x-states-json-over-lifted-model", ["states", "--blocks", "3", "--json"], "model.json"),
    ("x-plan-json-over-lifted-rules", ["plan", "--start", "CBA", "--goal", "BAC", "--json"], "lr.json"),
    ("x-plan-json-over-run-report", ["plan", "--start", "CBA", "--goal", "BAC", "--json"], "sh/run-report.json"),
])
@pytest.mark.parametrize("overwrite", [[], ["--overwrite"]])
def test_a_report_never_replaces_a_model(here, case, argv, target, overwrite):
    before = digest(here)
    run = csql(here, *argv, target, *overwrite)
    run.refused(target)
    assert digest(here) == before


def test_x_evaluate_json_over_lifted_model(here):
    before = digest(here)
    run = csql(here, "evaluate", "--blocks", "8", "--planner", "gn1", "--pairs", "1", "--quiet", "--json",
               "model.json", "--overwrite")
    run.refused("model.json")
    assert digest(here) == before


def test_the_registry_knows_every_model_the_tool_writes(here):
    assert formats.sniff(here / "model.json") == formats.LIFTED_Q
    assert formats.sniff(here / "lr.json") == formats.LIFTED_RULES
    assert formats.sniff(here / "sh") == formats.SHARDS
    for name in ("model.json", "lr.json", "sh/run-report.json", "sh/manifest.json", "sh/shard-00000.bin"):
        assert formats.model_kind(here / name) is not None, name
    (here / "report.json").write_text('{"format": "csql-sim plan report", "version": 1}\n')
    assert formats.model_kind(here / "report.json") is None


def test_a_report_still_replaces_a_report(here):
    assert csql(here, "plan", "--start", "CBA", "--goal", "BAC", "--json", "p.json").returncode == 0
    first = (here / "p.json").read_text()
    assert csql(here, "plan", "--start", "ABC", "--goal", "BAC", "--json", "p.json", "--overwrite").returncode == 0
    assert (here / "p.json").read_text() != first
