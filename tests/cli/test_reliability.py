"""Bad input and hostile files: exit status 2, one line on stderr, no traceback, nothing written."""

import importlib
import os
import re
import stat

import pytest
import yaml

from csql_sim.cli import main
from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.files.rulebase import RuleBase, load, save


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def refused(capsys, *argv, fragment=""):
    """Run a command that must be refused: status 2, one stderr line (containing fragment)."""
    code, _, err = run(capsys, *argv)
    assert code == 2, err
    assert err.count("\n") == 1 and re.match(r"csql-sim [a-z-]+: error: ", err), err
    assert "Traceback" not in err
    assert fragment in err, err
    return err


WORK = [  # where the commands compute: cycles, episodes, pruning, rendering
    ("csql_sim.jobs.experiment", "run_experiment"), ("csql_sim.jobs.evaluate", "evaluate"),
    ("csql_sim.learners.generalize.pruning", "prune"), ("csql_sim.jobs.render", "render_episode"),
]


def spy(monkeypatch, owner, name, calls, note=lambda *args: True, on_return=False):
    """Replace ``owner.name`` by a wrapper that appends ``name`` to ``calls`` when ``note(*args)``.

    ``on_return``: only once the call has returned (not when it raised).
    """
    real = getattr(owner, name)

    def wrapper(*args, **kwargs):
        noted = note(*args)
        if noted and not on_return:
            calls.append(name)
        out = real(*args, **kwargs)
        if noted and on_return:
            calls.append(name)
        return out

    monkeypatch.setattr(owner, name, wrapper)


@pytest.fixture
def work(monkeypatch):
    """The :data:`WORK` functions a command called, and ``make_learner`` once a learner was built."""
    import csql_sim.learners.training.tabular as training

    called = []
    for module, name in WORK:
        spy(monkeypatch, importlib.import_module(module), name, called)
    spy(monkeypatch, training, "make_learner", called, on_return=True)  # its training trials follow at once
    return called


@pytest.fixture
def parsed(monkeypatch):
    """YAML documents built into Python objects (aliases must be refused before this)."""
    built = []
    spy(monkeypatch, yaml, "load", built)
    return built


@pytest.fixture
def opened(monkeypatch):
    """Files opened for reading through os.fdopen (every guarded read of an input file)."""
    files = []
    spy(monkeypatch, os, "fdopen", files, note=lambda fd, mode="r", *rest: "r" in mode)
    return files


def usage_error(capsys, *argv, fragment=""):
    """An argparse error: SystemExit 2 and one line on stderr."""
    with pytest.raises(SystemExit) as info:
        main([str(a) for a in argv])
    err = capsys.readouterr().err
    assert info.value.code == 2 and err.count("\n") == 1 and fragment in err, err
    return err


@pytest.fixture(scope="module")
def rules3(tmp_path_factory):
    path = tmp_path_factory.mktemp("rules") / "r3.yaml"
    assert main(["train", "--trials", "50", "--out", str(path), "--quiet"]) == 0
    return path


# ------------------------------------------------------------------ lost work
def test_experiment_out_is_a_file_refused_before_any_cycle(capsys, tmp_path, work):
    afile = tmp_path / "afile"
    afile.write_text("keep me")
    refused(capsys, "experiment", "--out", afile, "--quiet", fragment="exists and is not a folder")
    assert work == []  # not one cycle was computed
    assert afile.read_text() == "keep me"


def test_evaluate_json_is_a_folder_refused_before_any_episode(capsys, tmp_path, work):
    refused(capsys, "evaluate", "--json", tmp_path, "--quiet", fragment="is a folder")
    assert work == []
    assert list(tmp_path.iterdir()) == []


def test_train_out_is_a_folder(capsys, tmp_path):
    refused(capsys, "train", "--out", tmp_path, "--quiet", fragment="is a folder; give a file name")
    assert list(tmp_path.iterdir()) == []


def test_parent_is_a_file(capsys, tmp_path):
    (tmp_path / "afile").write_text("")
    refused(capsys, "train", "--out", tmp_path / "afile" / "r.yaml", fragment="is not a folder")


@pytest.mark.parametrize("argv", [
    ["train", "--out", "r.yaml", "--trials", "5"],
    ["prune", "--rules", "RULES", "--out", "p.yaml"],
    ["experiment", "--out", "fig", "--cycles", "1", "--trials", "1"],
    ["evaluate", "--json", "e.json", "--pairs", "1"],
    ["render", "--start", "CBA", "--goal", "BAC"],
    ["demo", "--trials", "5"],
])
def test_read_only_folder_outputs_are_refused_before_work(capsys, read_only_dir, rules3, monkeypatch, work, argv):
    monkeypatch.chdir(read_only_dir)
    refused(capsys, *[str(rules3) if a == "RULES" else a for a in argv], fragment="cannot write in")
    assert work == []
    assert list(read_only_dir.iterdir()) == []


@pytest.mark.parametrize("argv", [
    ["states"], ["rules"], ["plan", "--start", "CBA", "--goal", "BAC"], ["show", "--rules", "RULES"],
    ["plan", "--rules", "RULES", "--pairs", "all"], ["bench", "--trials", "5", "--repeats", "1"],
])
def test_read_only_folder_readers_still_work(capsys, read_only_dir, rules3, monkeypatch, argv):
    monkeypatch.chdir(read_only_dir)
    code, out, err = run(capsys, *[str(rules3) if a == "RULES" else a for a in argv])
    assert code in (0, 1) and out and "Traceback" not in err
    assert list(read_only_dir.iterdir()) == []


def test_a_failed_final_write_keeps_the_results(capsys, read_only_dir, monkeypatch):
    import csql_sim.infra.files

    # the preflight passes (as if the folder became read-only during training) ...
    monkeypatch.setattr(csql_sim.infra.files, "check_output_file", lambda path, what="": path)
    err = refused(capsys, "train", "--out", read_only_dir / "r.yaml", "--trials", "20", "--quiet",
                  fragment="the results are kept in ")
    # ... and the trained rule base is where the message says, complete
    kept = err.rsplit("the results are kept in ", 1)[1].strip()
    assert sum(c.kind == "Q" for c in load(kept).classifiers) > 0
    os.unlink(kept)
    assert list(read_only_dir.iterdir()) == []


@pytest.mark.parametrize("argv", [
    ["train", "--out", "/dev/null", "--trials", "1"],
    ["evaluate", "--json", "/dev/null", "--pairs", "1"],
    ["prune", "--rules", "RULES", "--out", "/dev/null"],
])
def test_device_nodes_are_never_replaced(capsys, rules3, argv):
    refused(capsys, *[str(rules3) if a == "RULES" else a for a in argv], fragment="is a device, pipe or socket")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_experiment_into_a_device_is_refused(capsys):
    refused(capsys, "experiment", "--out", "/dev/null", fragment="exists and is not a folder")


@pytest.mark.parametrize("command", [
    ["render", "--start", "CBA", "--goal", "BAC"], ["demo"], ["train", "--out", "x.yaml"],
    ["experiment", "--out", "x"], ["bench"],
])
def test_negative_seeds_are_refused_by_the_parser(capsys, command):
    usage_error(capsys, *command, "--seed", "-1", fragment="--seed: must be a non-negative integer, got -1")


# ------------------------------------------------------------------ hostile files
LAUGHS = "".join(f"l{k}: &l{k} [{', '.join(['*l' + str(k - 1)] * 9) if k else 'lol'}]\n" for k in range(9))


def test_billion_laughs_in_a_rule_file(capsys, tmp_path, parsed):
    path = tmp_path / "laughs.yaml"
    path.write_text(LAUGHS + "format: csql-sim rule base\nversion: 2\nblocks: *l8\ncount: 0\nclassifiers: []\n")
    refused(capsys, "show", "--rules", path, fragment="YAML aliases (*l0) are not allowed")
    assert parsed == []  # refused from the parser's events: no alias was ever expanded


def test_billion_laughs_in_params(capsys, tmp_path, parsed, work):
    path = tmp_path / "params.yaml"
    path.write_text(LAUGHS + "eta: *l8\n")
    refused(capsys, "train", "--out", tmp_path / "r.yaml", "--params", path, fragment="aliases")
    assert parsed == [] and work == [] and not (tmp_path / "r.yaml").exists()


def test_deeply_nested_rule_file(capsys, tmp_path):
    path = tmp_path / "deep.yaml"
    path.write_text("[" * 1000 + "]" * 1000 + "\n")
    # PyYAML may refuse this depth itself, before our 32-level check: assert our promise only
    # (one line naming the file, exit 2), not whose wording it is.
    refused(capsys, "plan", "--rules", path, "--pairs", "all", fragment=str(path))


def test_show_dev_zero(capsys):
    refused(capsys, "show", "--rules", "/dev/zero", fragment="not a regular rule file")


def test_a_50_mb_file_is_refused_without_reading_it(capsys, tmp_path, opened, parsed):
    path = tmp_path / "big.yaml"
    path.write_text("x: " + "a" * (50 * 1024 * 1024) + "\n")
    refused(capsys, "show", "--rules", path, fragment="above the 16,777,216-byte limit")
    assert opened == [] and parsed == []  # refused from its size: not one byte read, nothing parsed


def test_a_rule_file_cut_at_a_line_boundary(capsys, rules3, tmp_path):
    lines = rules3.read_text().splitlines(keepends=True)
    cut = tmp_path / "cut.yaml"
    cut.write_text("".join(lines[:-10]))
    refused(capsys, "plan", "--rules", cut, "--pairs", "all", fragment="but its header says")


def test_a_nan_q_value(capsys, rules3, tmp_path):
    bad = tmp_path / "nan.yaml"
    bad.write_text(rules3.read_text().replace(", q: ", ", q: .nan, x: ", 1))
    refused(capsys, "show", "--rules", bad, fragment="q must be finite, got nan")


def test_a_3_block_file_relabelled_as_2(capsys, rules3, tmp_path):
    bad = tmp_path / "two.yaml"
    bad.write_text(rules3.read_text().replace("\nblocks: 3\n", "\nblocks: 2\n"))
    refused(capsys, "show", "--rules", bad, fragment="but the file is for 2 blocks")


def test_a_4_block_rule_file_with_a_3_block_task_names_the_file(capsys, tmp_path):
    path = save(tmp_path / "r4.yaml", RuleBase(blocks=4, classifiers=list(r_classifiers(4))))
    fragment = f"rule file {str(path)!r} is for 4 blocks, but the task CBA -> BAC has 3"
    refused(capsys, "plan", "--rules", path, "--start", "CBA", "--goal", "BAC", fragment=fragment)
    refused(capsys, "show", "--rules", path, "--start", "CBA", "--goal", "BAC", fragment=fragment)


# ------------------------------------------------------------------ parameters
@pytest.mark.parametrize(("text", "fragment"), [
    ("gamma: .nan\n", "gamma must be in [0, 1], got nan"), ("gamma: 1.5\n", "gamma must be in [0, 1]"),
    ("t0: -1\n", "t0 must be > 0"), ("eta: 0\n", "eta must be in (0, 1]"), ("t_decay: 2\n", "t_decay"),
    ("step_cap: 0\n", "step_cap must be >= 1"), ("age_unit: 0\n", "age_unit must be > 0"),
])
def test_out_of_range_params(capsys, tmp_path, text, fragment):
    params = tmp_path / "p.yaml"
    params.write_text(text)
    refused(capsys, "train", "--out", tmp_path / "r.yaml", "--params", params, fragment=fragment)
    assert not (tmp_path / "r.yaml").exists()


@pytest.mark.parametrize("value", ["nan", "2", "-0.1", "inf"])
def test_prune_threshold_out_of_range(capsys, rules3, tmp_path, value):
    usage_error(capsys, "prune", "--rules", rules3, "--threshold", value, "--out", tmp_path / "p.yaml",
                fragment="must be a number in [0, 1]")
    assert not (tmp_path / "p.yaml").exists()


# ------------------------------------------------------------------ output hygiene
def test_methods_are_not_duplicated(capsys, tmp_path):
    code, _, _ = run(capsys, "experiment", "--methods", "cs-ql,CS-QL, cs-ql", "--cycles", "1", "--trials", "50",
                     "--workers", "1", "--out", tmp_path, "--quiet")
    assert code == 0
    rows = (tmp_path / "figure7.csv").read_text().splitlines()[1:]
    assert {r.split(",")[0] for r in rows} == {"cs-ql"} and len(rows) == 2  # trials 0 and 50, once each


@pytest.mark.parametrize("command", [
    ["train", "--out", "r.yaml"], ["experiment", "--out", "x"], ["evaluate"],
    ["render", "--start", "CBA", "--goal", "BAC"], ["demo"],
])
def test_quiet_everywhere_with_no_progress_as_alias(command):
    from csql_sim.cli import build_parser

    for flag in ("--quiet", "--no-progress"):
        assert build_parser().parse_args([*command, flag]).quiet is True
    assert build_parser().parse_args(command).quiet is False


def test_workers_above_the_cores_warn_and_are_capped(capsys, tmp_path):
    from csql_sim.infra.workers import worker_count

    cores = os.cpu_count() or 1
    assert worker_count(1000, 3) == min(3, cores) and worker_count(None, 1) == 1 and worker_count(2, 0) == 1
    code, _, err = run(capsys, "evaluate", "--pairs", "1", "--workers", "1000", "--quiet")
    assert code == 0
    assert err == f"csql-sim evaluate: warning: --workers 1000 is more than the {cores} cores; using {cores}\n"
