import csv
import json

import pytest

from csql_sim.cli import main
from csql_sim.core.files.rulebase import load


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def rule_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("rules")
    rules, pruned = folder / "rules.yaml", folder / "pruned.yaml"
    assert main(["train", "--out", str(rules), "--no-progress"]) == 0
    assert main(["prune", "--rules", str(rules), "--threshold", "0.1", "--out", str(pruned)]) == 0
    return rules, pruned


def test_train_prune_plan_all_optimal(rule_files, capsys):
    rules, pruned = rule_files
    assert sum(c.kind == "Q" for c in load(rules).classifiers) == 882
    assert sum(c.kind == "Q" for c in load(pruned).classifiers) == 462
    code, out, _ = run(capsys, "plan", "--rules", str(pruned), "--pairs", "all")
    assert code == 0 and "optimal: 462" in out


def test_prune_prints_counts(rule_files, capsys, tmp_path):
    rules, _ = rule_files
    code, out, _ = run(capsys, "prune", "--rules", str(rules), "--out", str(tmp_path / "p.yaml"))
    assert code == 0 and "882 before, 462 after" in out


def test_show_greedy_path_of_the_test_task(rule_files, capsys):
    _, pruned = rule_files
    code, out, _ = run(capsys, "show", "--rules", str(pruned), "--start", "CBA", "--goal", "BAC")
    lines = out.splitlines()
    assert code == 0 and len(lines) == 9
    assert lines[1].split()[:3] == ["Q", "S0100000bct0000C", "A10000001000ab00"]
    assert lines[-1].split()[4] == "1.000000"


def test_same_seed_same_file(rule_files, tmp_path):
    rules, _ = rule_files
    again = tmp_path / "again.yaml"
    assert main(["train", "--out", str(again), "--no-progress"]) == 0
    assert again.read_text() == rules.read_text()


def test_experiment_writes_csv_and_png(tmp_path, capsys):
    code, out, _ = run(capsys, "experiment", "--methods", "cs-ql,lt-ql", "--cycles", "2", "--trials", "100",
                       "--workers", "1", "--out", str(tmp_path), "--no-progress")
    assert code == 0 and "cs-ql" in out and "lt-ql" in out
    assert "statements about Figure 7" in out
    assert "LT-QL starts near 1400 steps: paper about 1400 (accepted 700-2100); measured lt-ql" in out
    assert "does not hold  LT-QL reaches the optimal 8 steps by about trial 1150: paper about trial 1150 " \
           "(accepted 1000-1300); measured first at the optimum: lt-ql never" in out
    rows = list(csv.DictReader((tmp_path / "figure7.csv").open()))
    assert len(rows) == 2 * 3 and rows[0]["method"] == "cs-ql" and rows[-1]["trial"] == "100"
    assert (tmp_path / "figure7.png").read_bytes()[:4] == b"\x89PNG"
    assert "test task CBA -> BAC (3 blocks), optimum: 8 steps" in out
    sidecar = json.loads((tmp_path / "figure7.json").read_text())
    prov = sidecar["provenance"]
    assert prov["version"] and prov["parameters"]["cycles"] == 2 and prov["parameters"]["trials"] == 100
    assert prov["parameters"]["learner_params"]["cs-ql"]["t_decay"] == 0.9955


def test_experiment_json_records_params_overrides_and_names_the_n4_test_task(tmp_path, capsys):
    params = tmp_path / "p.yaml"
    params.write_text("cs-ql: {eta: 0.25}\n")
    code, out, _ = run(capsys, "experiment", "--methods", "cs-ql", "--cycles", "1", "--trials", "0",
                       "--blocks", "4", "--out", str(tmp_path), "--quiet", "--params", str(params), "--json")
    doc = json.loads(out)
    assert code == 0 and doc["test_task"] == {"start": "CBDA", "goal": "BCDA", "optimal_length": 12}
    assert doc["provenance"]["parameters"]["learner_params"]["cs-ql"]["eta"] == 0.25
    assert doc["methods"][0]["method"] == "cs-ql"


def test_params_prints_yaml_that_params_accepts(tmp_path, capsys):
    import dataclasses

    from csql_sim.learners.paper.params import defaults_for_blocks, load_params

    code, out, _ = run(capsys, "params", "--method", "lt-ql", "--blocks", "4")
    assert code == 0 and out.startswith("# csql-sim")
    path = tmp_path / "lt.yaml"
    assert "eta: 0.5\n" in out
    path.write_text(out.replace("eta: 0.5\n", "eta: 0.3\n"))
    assert load_params(path, "lt-ql", 4) == dataclasses.replace(defaults_for_blocks("lt-ql", 4), eta=0.3)
    rules = tmp_path / "r.npz"  # the compact form: 35,712 classifiers read back in a moment, not half a minute
    assert main(["train", "--method", "lt-ql", "--trials", "20", "--params", str(path), "--out", str(rules),
                 "--blocks", "4", "--quiet"]) == 0
    prov = load(rules).meta["provenance"]
    assert prov["parameters"]["learner_params"]["eta"] == 0.3 and prov["parameters"]["params_file"] == str(path)
    assert prov["version"] == __import__("csql_sim").__version__


def test_show_and_bench_json(rule_files, capsys):
    _, pruned = rule_files
    code, out, _ = run(capsys, "show", "--rules", str(pruned), "--start", "CBA", "--goal", "BAC", "--json")
    doc = json.loads(out)
    assert code == 0 and len(doc["classifiers"]) == 8 and doc["classifiers"][-1]["q"] == 1.0
    code, out, _ = run(capsys, "bench", "--trials", "50", "--repeats", "1", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["trials"] == 50 and doc["ratio"] > 0 and doc["provenance"]["parameters"]["seed"] == 0


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["show", "--rules", "{missing}"], "no such rule file"),
        (["prune", "--rules", "{truncated}", "--out", "{out}"], "truncated or corrupt"),
        (["show", "--rules", "{foreign}"], "not a csql-sim rule base"),
        (["train", "--params", "{bad_params}", "--out", "{out}"], "unknown parameter"),
        (["show", "--rules", "{rules}", "--start", "CBA"], "both --start and --goal"),
        (["experiment", "--methods", "cs-ql,nope", "--out", "{out}"], "unknown method"),
        (["train", "--trials", "-3", "--out", "{out}"], "non-negative"),
    ],
)
def test_error_paths_one_line_exit_2(argv, fragment, rule_files, tmp_path, capsys):
    rules, _ = rule_files
    truncated = tmp_path / "t.yaml"
    truncated.write_text(rules.read_text()[:300])
    foreign = tmp_path / "f.yaml"
    foreign.write_text("hello: world\n")
    bad = tmp_path / "bad.yaml"
    bad.write_text("etta: 1\n")
    names = {"missing": tmp_path / "none.yaml", "truncated": truncated, "foreign": foreign,
             "bad_params": bad, "out": tmp_path / "o.yaml", "rules": rules}
    args = [a.format(**{k: str(v) for k, v in names.items()}) for a in argv]
    try:
        code = main(args)
    except SystemExit as exc:  # argparse usage errors
        code = exc.code
    _, err = capsys.readouterr()
    assert code == 2
    assert fragment in err and len(err.strip().splitlines()) == 1


def test_a_lifted_or_sharded_file_where_a_ground_rule_file_is_needed_says_what_it_is(tmp_path, capsys):
    """Issue 28 item 7: 'generalize --rules lifted.json' said 'not a csql-sim rule base' of train-lifted's output."""
    lifted = tmp_path / "l.json"
    assert main(["train-lifted", "--quiet", "--trials", "20", "--sizes", "3", "--goals", "2",
                 "--out", str(lifted)]) == 0
    capsys.readouterr()
    for argv in (["generalize", "--rules", str(lifted), "--out", str(tmp_path / "g.yaml")],
                 ["prune", "--rules", str(lifted), "--out", str(tmp_path / "p.yaml")]):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "lifted q-classifiers" in err and f"plan --rules {lifted}" in err, err
    assert main(["show", "--rules", str(lifted)]) == 0  # and show displays it
    assert "lifted Q-classifiers" in capsys.readouterr().out
