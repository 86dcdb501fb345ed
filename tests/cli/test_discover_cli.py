import json

from csql_sim.cli import main
from csql_sim.core.classifiers.r_classifier import load_paper_rules
from csql_sim.core.files import rulebase
from csql_sim.discovery import transition_log
from csql_sim.discovery.induction import induce_rules


def test_discover_symbolic_writes_rules_log_and_report(tmp_path, capsys):
    out, log, rep = tmp_path / "rules.yaml", tmp_path / "t.jsonl", tmp_path / "r.json"
    code = main(["discover", "--world", "symbolic", "--seed", "2", "--quiet", "--out", str(out), "--log", str(log),
                 "--json", str(rep)])
    assert code == 0
    rb = rulebase.load(out)
    want = [(c.condition, c.action) for c in load_paper_rules()]
    assert [(c.condition, c.action) for c in rb.classifiers] == want
    assert all(c.kind == "R" for c in rb.classifiers)
    n, transitions = transition_log.load(log)
    assert n == 3 and [(c.condition, c.action) for c in induce_rules(transitions, n)] == want
    report = json.loads(rep.read_text())
    assert report["rules"] == 36 and report["all_equal"] and report["transitions"] == len(transitions)
    assert report["failed_attempts"] == sum(not t.ok for t in transitions)
    assert report["written"] == [str(out), str(log)] and "provenance" in report
    assert capsys.readouterr().out == ""  # --json FILE: JSON instead of the text report


def test_discover_prints_text_or_json_to_stdout(tmp_path, capsys):
    args = ["discover", "--world", "symbolic", "--seed", "2", "--quiet", "--out", str(tmp_path / "r.yaml")]
    assert main(args) == 0
    assert "36 of 36 equal" in capsys.readouterr().out
    assert main([*args, "--json", "--overwrite"]) == 0
    assert json.loads(capsys.readouterr().out)["rules"] == 36


def test_discover_bad_input_is_one_line_exit_2(tmp_path, capsys):
    assert main(["discover", "--world", "symbolic", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is a folder" in err
