"""``csql-sim train-lifted``: the file written and read back; bad options refused."""

import json

import pytest

from csql_sim.cli import main
from csql_sim.core.policies.lifted_policy import load_lifted_policy


def test_train_lifted_writes_a_file_plan_can_use(tmp_path, capsys):
    out = tmp_path / "l.json"
    assert main(["train-lifted", "--trials", "60", "--out", str(out), "--quiet"]) == 0
    text = capsys.readouterr().out
    assert f"wrote {out}" in text
    policy = load_lifted_policy(out)
    doc = json.loads(out.read_text())
    assert doc["meta"]["training"]["trials"] == 60 and doc["meta"]["seed"] == 0
    assert doc["meta"]["training"]["lifted_q_classifiers"] == len(policy.classifiers)
    assert main(["plan", "--rules", str(out), "--start", "A,B,C,D,E,F,G,H", "--goal", "HGFEDCBA", "--json"]) in (0, 1)
    assert capsys.readouterr().out


@pytest.mark.parametrize(("argv", "names"), [
    (["--sizes", "6"], "--sizes"),
    (["--sizes", "x"], "--sizes"),
    (["--trials", "0"], "--trials"),
    (["--atoms", "misplaced,stuck"], "--atoms"),
])
def test_bad_options_are_refused_in_one_line(tmp_path, capsys, argv, names):
    out = tmp_path / "l.json"
    with pytest.raises(SystemExit) as exit_:  # argparse's usage error
        main(["train-lifted", "--out", str(out), *argv])
    assert exit_.value.code == 2
    captured = capsys.readouterr()
    assert captured.err.count("\n") == 1 and names in captured.err and "Traceback" not in captured.err
    assert not out.exists()


def test_the_atoms_read_are_chosen_by_name_and_recorded(tmp_path, capsys):
    out = tmp_path / "l.json"
    argv = ["train-lifted", "--trials", "100", "--atoms", "misplaced,goal-on,ready,least-stuck(?x)", "--out", str(out),
            "--quiet", "--json"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["params"]["atoms"] == ["misplaced(?x)", "goal-on(?x,?d)", "ready(?d)", "least-stuck(?x)"]
    conditions = [c.condition for c in load_lifted_policy(out).classifiers]
    assert conditions and all(set(c[3:5] + c[6:]) == {"#"} for c in conditions)
    assert any(c[5] != "#" for c in conditions)  # least-stuck read when asked for


def test_atoms_with_generated_features_is_refused_before_training(tmp_path, capsys):
    out = tmp_path / "l.json"
    assert main(["train-lifted", "--features", "generated", "--atoms", "all", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--atoms" in err and not out.exists()


def test_an_existing_file_of_someone_else_is_kept(tmp_path, capsys):
    out = tmp_path / "l.json"
    out.write_text("mine")
    assert main(["train-lifted", "--trials", "5", "--out", str(out)]) == 2
    assert out.read_text() == "mine"


@pytest.mark.parametrize("domain", ["move", "4op"])
def test_train_lifted_over_generated_features_writes_a_file_plan_reads(tmp_path, capsys, domain):
    out = tmp_path / "g.json"
    argv = ["train-lifted", "--features", "generated", "--domain", domain, "--complexity", "4", "--trials", "120",
            "--goals", "10", "--sizes", "4", "--committee", "1", "--out", str(out), "--quiet", "--json"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    written = json.loads(out.read_text())
    assert written["formulation"] == domain and "(define (domain" in written["domain"]
    assert doc["atoms"] == written["atoms"] and doc["training"]["features"]["complexity"] == 4
    assert doc["params"]["features"] == "generated" and doc["training"]["features"]["literals"] >= len(doc["atoms"])
    assert main(["plan", "--rules", str(out), "--start", "A,B,C,D,E,F,G", "--goal", "GFEDCBA", "--json"]) in (0, 1)
    assert json.loads(capsys.readouterr().out)


@pytest.mark.parametrize(("argv", "names"), [
    (["--features", "learned"], "--features"),
    (["--domain", "nowhere.pddl"], "--domain"),
    (["--complexity", "11"], "--complexity"),
])
def test_bad_feature_options_are_refused_in_one_line(tmp_path, capsys, argv, names):
    out = tmp_path / "g.json"
    with pytest.raises(SystemExit) as exit_:
        main(["train-lifted", "--out", str(out), "--features", "generated", *argv])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and names in err and not out.exists()


def test_a_domain_that_is_not_a_blocks_world_is_one_line(tmp_path, capsys):
    domain = tmp_path / "d.pddl"
    domain.write_text("(define (domain d) (:predicates (at ?x)) (:action go :parameters (?x) :precondition (at ?x) "
                      ":effect (not (at ?x))))")
    out = tmp_path / "g.json"
    assert main(["train-lifted", "--features", "generated", "--domain", str(domain), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "d.pddl" in err and not out.exists()


def test_a_committee_is_written_member_by_member_and_plans(tmp_path, capsys):
    out = tmp_path / "c.json"
    argv = ["train-lifted", "--features", "generated", "--formulation", "move", "--complexity", "4", "--trials", "120",
            "--goals", "10", "--sizes", "4", "--committee", "2", "--out", str(out), "--quiet", "--json"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    written = json.loads(out.read_text())
    assert written["version"] == 2 and len(written["members"]) == 2 and doc["members"] == written["members"]
    assert doc["training"]["committee"] == 2 and [m["trials"] for m in doc["training"]["members"]] == [120, 120]
    single = tmp_path / "s.json"
    assert main([*argv[:-6], "--committee", "1", "--out", str(single), "--quiet", "--json"]) == 0  # the same seed
    capsys.readouterr()
    one = json.loads(single.read_text())
    assert one["version"] == 1 and written["members"][0] == {"atoms": one["atoms"], "classifiers": one["classifiers"]}
    assert main(["plan", "--rules", str(out), "--start", "A,B,C,D,E,F,G", "--goal", "GFEDCBA", "--json"]) in (0, 1)
    assert json.loads(capsys.readouterr().out)
    assert main(["show", "--rules", str(out), "--json"]) == 0
    lines = json.loads(capsys.readouterr().out)["classifiers"]
    second = lines.index("member 2:")
    assert lines[lines.index("member 1:") + 1:second][:len(one["classifiers"])] == one["classifiers"]
    assert sum(line.startswith("literal 1: ") for line in lines) == 2


def test_generated_features_learn_a_committee_of_three_by_default(tmp_path, capsys):
    out = tmp_path / "d.json"
    argv = ["train-lifted", "--features", "generated", "--formulation", "move", "--complexity", "4", "--trials", "60",
            "--goals", "6", "--sizes", "4", "--out", str(out), "--quiet", "--json"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    written = json.loads(out.read_text())
    assert written["version"] == 2 and len(written["members"]) == 3 and doc["training"]["committee"] == 3
    assert doc["provenance"]["parameters"]["committee"] == 3


@pytest.mark.parametrize(("argv", "names"), [
    (["--committee", "2"], "--committee"),  # with the given atoms
    (["--features", "generated", "--committee", "10"], "--committee"),
    (["--features", "generated", "--committee", "0"], "--committee"),
    (["--features", "generated", "--committee", "2", "--workers", "0"], "--workers"),
])
def test_a_bad_committee_is_refused_in_one_line_before_training(tmp_path, capsys, argv, names):
    out = tmp_path / "c.json"
    try:
        code = main(["train-lifted", "--out", str(out), *argv])
    except SystemExit as exit_:  # argparse's usage error
        code = exit_.code
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and names in err and not out.exists()
