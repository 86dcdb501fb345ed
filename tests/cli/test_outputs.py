"""Outputs through the CLI: no file replaced without asking, clashes and bad outputs refused before the work.

Each refusal is exit status 2, exactly one line on stderr naming the file, and nothing
written or changed (the "Reliable anywhere" sweep's cases, items 1, 2, 5 and 6).
"""

import importlib
import json
import os
import re

import pytest

from csql_sim.cli import main

SMALL_DISCOVER = ["discover", "--world", "symbolic", "--transitions", "60", "--quiet"]


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def refused(capsys, *argv, names=()):
    """A refused command: status 2, one stderr line, naming every string of ``names``."""
    code, _, err = run(capsys, *argv)
    assert code == 2, err
    assert err.count("\n") == 1 and re.match(r"csql-sim [a-z-]+: error: ", err) and "Traceback" not in err, err
    for name in names:
        assert name in err, err
    return err


def usage_error(capsys, *argv, names=()):
    """An argparse refusal: SystemExit 2, one stderr line naming every string of ``names``."""
    with pytest.raises(SystemExit) as info:
        main([str(a) for a in argv])
    err = capsys.readouterr().err
    assert info.value.code == 2 and err.count("\n") == 1, err
    for name in names:
        assert name in err, err


def snapshot(folder):
    """Every path under ``folder`` with its bytes (None for a folder)."""
    return {str(p.relative_to(folder)): (None if p.is_dir() else p.read_bytes()) for p in sorted(folder.rglob("*"))}


WORK = [("csql_sim.jobs.discover", "discover"), ("csql_sim.jobs.render", "render_episode"),
        ("csql_sim.jobs.experiment", "run_experiment"), ("csql_sim.jobs.scaling", "run_scaling"),
        ("csql_sim.jobs.evaluate", "evaluate"), ("csql_sim.learners.training", "train"),
        ("csql_sim.learners.training", "train_learner"), ("csql_sim.core.policies.rollout", "check_pairs")]


@pytest.fixture
def no_work(monkeypatch):
    """The long work of every command: the test fails if any of it starts."""
    def forbidden(name):
        def call(*args, **kwargs):
            raise AssertionError(f"{name} ran although the outputs were bad")
        return call

    for module, name in WORK:
        monkeypatch.setattr(importlib.import_module(module), name, forbidden(name))


# ------------------------------------------------------------------ 1. no file replaced without asking
@pytest.mark.parametrize("argv, existing", [
    (SMALL_DISCOVER, "rules.yaml"),
    (["render", "--start", "CBA", "--goal", "BAC", "--quiet"], "video.mp4"),
    (["render", "--start", "CBA", "--goal", "BAC", "--quiet"], "video.mp4.json"),
    (["demo", "--trials", "5", "--quiet"], "out/pruned.yaml"),
])
def test_an_existing_default_output_is_refused(capsys, tmp_path, monkeypatch, no_work, argv, existing):
    monkeypatch.chdir(tmp_path)
    (tmp_path / existing).parent.mkdir(exist_ok=True)
    (tmp_path / existing).write_text("a file of the user's\n")
    before = snapshot(tmp_path)
    refused(capsys, *argv, names=(existing, "--out", "--overwrite"))
    assert snapshot(tmp_path) == before


def test_the_default_rule_file_is_replaced_with_overwrite(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "rules.yaml").write_text("mine\n")
    code, _, err = run(capsys, *SMALL_DISCOVER, "--overwrite")
    assert code in (0, 1), err
    assert (tmp_path / "rules.yaml").read_text().startswith("format: csql-sim rule base")


def test_an_existing_output_is_replaced_only_with_overwrite(capsys, tmp_path, monkeypatch):
    """Any existing file, even our own output of the same kind (a 3,000-trial model, a video): issue 28 item 15."""
    monkeypatch.chdir(tmp_path)
    assert run(capsys, *SMALL_DISCOVER, "--out", "r.yaml")[0] in (0, 1)
    first = (tmp_path / "r.yaml").read_bytes()
    refused(capsys, *SMALL_DISCOVER, "--seed", "1", "--out", "r.yaml", names=("r.yaml", "--overwrite"))
    assert (tmp_path / "r.yaml").read_bytes() == first
    (tmp_path / "notes.yaml").write_text("format: my notes\n")
    refused(capsys, *SMALL_DISCOVER, "--out", "notes.yaml", names=("notes.yaml", "--overwrite"))
    assert (tmp_path / "notes.yaml").read_text() == "format: my notes\n"
    assert run(capsys, "states", "--json", "r.json")[0] == 0
    refused(capsys, "states", "--json", "r.json", names=("r.json", "--overwrite"))
    (tmp_path / "r.json").write_text('{"a": 1}\n')
    assert run(capsys, "states", "--json", "r.json", "--overwrite")[0] == 0
    assert json.loads((tmp_path / "r.json").read_text())["format"] == "csql-sim states report"


@pytest.mark.parametrize("argv", [
    ["show", "--rules", "r.yaml", "--json", "r.yaml"],
    ["prune", "--rules", "r.yaml", "--out", "r.yaml"],
    ["plan", "--rules", "r.yaml", "--start", "CBA", "--goal", "BAC", "--json", "r.yaml"],
    ["train", "--domain-rules", "r.yaml", "--out", "r.yaml", "--overwrite"],
])
def test_no_output_is_an_input(capsys, tmp_path, monkeypatch, argv):
    monkeypatch.chdir(tmp_path)
    assert main(["train", "--trials", "5", "--out", "r.yaml", "--quiet"]) == 0
    capsys.readouterr()
    before = snapshot(tmp_path)
    refused(capsys, *argv, names=("'r.yaml'", "reads"))
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("argv, name", [
    (["discover", "--world", "symbolic", "--out", "x.yaml", "--log", "x.yaml"], "x.yaml"),
    (["discover", "--world", "symbolic", "--out", "x", "--json", "x"], "'x'"),
    (["evaluate", "--json", "p.png", "--plot", "p.png"], "p.png"),
    (["experiment", "--json", "d/figure7.json", "--out", "d"], "figure7.json"),
    (["experiment", "--json", "./d/../d/figure7.json", "--out", "d"], "figure7.json"),  # the same after resolving
    (["discover", "--world", "symbolic", "--out", "x", "--log", "x/t.jsonl"], "'x'"),
])
def test_two_outputs_of_one_command_may_not_be_the_same_path(capsys, tmp_path, monkeypatch, no_work, argv, name):
    monkeypatch.chdir(tmp_path)
    err = refused(capsys, *argv, names=(name,))
    assert "same path" in err or "folder" in err
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ 2. every output checked before the work
@pytest.mark.parametrize("argv, folder", [
    (["experiment", "--out", "xx", "--json", "xx", "--quiet"], None),
    (["experiment", "--out", "d", "--quiet"], "d/figure7.png"),
    (["demo", "--out", "d", "--quiet"], "d/rules.yaml"),
    (["render", "--start", "CBA", "--goal", "BAC", "--out", "v.mp4", "--quiet"], "v.mp4.json"),
    (["scaling", "--out", "s", "--blocks", "2", "--quiet"], "s/scaling.csv"),
])
def test_outputs_are_checked_before_the_work(capsys, tmp_path, monkeypatch, no_work, argv, folder):
    monkeypatch.chdir(tmp_path)
    if folder:
        (tmp_path / folder).mkdir(parents=True)
    before = snapshot(tmp_path)
    refused(capsys, *argv, names=(folder or "xx",))
    assert snapshot(tmp_path) == before


# ------------------------------------------------------------------ 5. input ignored, empty paths
def test_plan_refuses_rules_it_would_not_read(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "garbage.yaml").write_text("not: a rule file\n")
    refused(capsys, "plan", "--planner", "bfs", "--rules", "garbage.yaml", "--start", "CBA", "--goal", "BAC",
            names=("garbage.yaml", "--planner bfs"))


@pytest.mark.parametrize("argv, option", [
    (["plan", "--rules", "", "--start", "CBA", "--goal", "BAC"], "--rules"),
    (["discover", "--world", "symbolic", "--log", ""], "--log"),
    (["evaluate", "--plot", ""], "--plot"),
    (["render", "--rules", "", "--start", "CBA", "--goal", "BAC"], "--rules"),
    (["states", "--json", ""], "--json"),
    (["train", "--out", ""], "--out"),
    (["demo", "--out", ""], "--out"),
    (["show", "--rules", ""], "rules"),
])
def test_empty_paths_are_refused(capsys, tmp_path, monkeypatch, no_work, argv, option):
    monkeypatch.chdir(tmp_path)
    usage_error(capsys, *argv, names=(option, "empty path"))
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ 6. JSON reports carry a format version
@pytest.mark.parametrize("argv, name", [
    (["states", "--blocks", "2"], "csql-sim states report"),
    (["rules", "--blocks", "2"], "csql-sim rules report"),
    (["plan", "--start", "CBA", "--goal", "BAC"], "csql-sim plan report"),
    (["plan", "--pairs", "3"], "csql-sim plan pairs report"),
    ([*SMALL_DISCOVER, "--out", "r.yaml"], "csql-sim discovery report"),
    (["bench", "--trials", "5", "--repeats", "1"], "csql-sim bench report"),
])
def test_json_reports_name_their_format_and_version(capsys, tmp_path, monkeypatch, argv, name):
    monkeypatch.chdir(tmp_path)
    code, _, err = run(capsys, *argv, "--json", "report.json")
    assert code in (0, 1), err
    doc = json.loads((tmp_path / "report.json").read_text())
    assert list(doc)[:2] == ["format", "version"] and doc["format"] == name and doc["version"] == 1


def test_folder_reports_and_sidecars_name_their_format(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert run(capsys, "experiment", "--out", "e", "--cycles", "1", "--trials", "4", "--blocks", "2",
               "--methods", "lt-ql", "--json", "e.json", "--quiet")[0] == 0
    assert run(capsys, "scaling", "--out", "s", "--blocks", "2", "--methods", "lt-ql", "--max-trials", "20",
               "--quiet")[0] == 0
    for path, name, version in (("e/figure7.json", "experiment", 1), ("e.json", "experiment", 1),
                                ("s/scaling.json", "scaling", 2)):
        doc = json.loads((tmp_path / path).read_text())
        assert (doc["format"], doc["version"]) == (f"csql-sim {name} report", version), path
    # a second run into the same folder needs --overwrite, even for its own files
    code, _, err = run(capsys, "scaling", "--out", "s", "--blocks", "2", "--methods", "lt-ql", "--max-trials", "20",
                       "--quiet")
    assert code == 2 and "--overwrite" in err
    assert run(capsys, "scaling", "--out", "s", "--blocks", "2", "--methods", "lt-ql", "--max-trials", "20",
               "--quiet", "--overwrite")[0] == 0


def test_json_to_a_symbolic_link_writes_the_file_it_points_to(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert run(capsys, "states", "--json", "target.json")[0] == 0
    os.symlink("target.json", tmp_path / "link.json")
    assert run(capsys, "rules", "--json", "link.json", "--overwrite")[0] == 0
    assert os.readlink(tmp_path / "link.json") == "target.json"  # the link is kept
    assert json.loads((tmp_path / "target.json").read_text())["format"] == "csql-sim rules report"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.json", "target.json"]
