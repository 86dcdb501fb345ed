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
])
def test_bad_options_are_refused_in_one_line(tmp_path, capsys, argv, names):
    out = tmp_path / "l.json"
    with pytest.raises(SystemExit) as exit_:  # argparse's usage error
        main(["train-lifted", "--out", str(out), *argv])
    assert exit_.value.code == 2
    captured = capsys.readouterr()
    assert captured.err.count("\n") == 1 and names in captured.err and "Traceback" not in captured.err
    assert not out.exists()


def test_an_existing_file_of_someone_else_is_kept(tmp_path, capsys):
    out = tmp_path / "l.json"
    out.write_text("mine")
    assert main(["train-lifted", "--trials", "5", "--out", str(out)]) == 2
    assert out.read_text() == "mine"
