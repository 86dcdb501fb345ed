"""Every command takes --quiet and --json; each size limit is one constant, stated alike in help, docs and errors."""

import json
from pathlib import Path

import pytest

from csql_sim.cli import build_parser, main
from csql_sim.core.files.pddl_import import MAX_DRAWN_BLOCKS, MAX_PLANNED_BLOCKS

DOCS = Path(__file__).resolve().parents[2] / "docs"


def commands():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    return sub.choices


@pytest.mark.parametrize("name", sorted(commands()))
def test_every_command_takes_quiet_and_json(name):
    options = commands()[name]._option_string_actions
    assert "--quiet" in options and "--json" in options


def test_json_replaces_the_text_of_pddl_params_and_train(capsys, tmp_path):
    assert main(["pddl", "--start", "CBA", "--goal", "BAC", "--out", str(tmp_path / "t"), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["blocks"] == 3 and sorted(Path(f).name for f in doc["files"]) == ["domain.pddl", "problem.pddl"]
    assert main(["params", "--method", "cs-ql", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["params"]
    assert main(["train", "--trials", "5", "--out", str(tmp_path / "r.yaml"), "--json", "--quiet"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["trials"] == 5 and doc["q_classifiers"] > 0 and Path(doc["out"]).is_file()
    assert main(["prune", "--rules", str(tmp_path / "r.yaml"), "--out", str(tmp_path / "p.yaml"), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["q_after"] <= doc["q_before"] and Path(doc["out"]).is_file()


def test_the_planning_limit_is_one_number_in_help_docs_and_errors(capsys, tmp_path):
    stated = f"{MAX_PLANNED_BLOCKS:,}"
    for name in ("plan", "validate", "train-lifted"):
        assert stated in " ".join(commands()[name].format_help().split()), name
    drawn = f"2..{MAX_DRAWN_BLOCKS}"
    assert drawn in " ".join(commands()["problems"].format_help().split())
    assert stated in (DOCS / "cli.md").read_text() and drawn in (DOCS / "cli.md").read_text()
    names = " ".join(f"b{i}" for i in range(MAX_PLANNED_BLOCKS + 1))
    init = " ".join(f"(ontable b{i}) (clear b{i})" for i in range(MAX_PLANNED_BLOCKS + 1))
    problem = tmp_path / "big.pddl"
    problem.write_text(f"(define (problem big) (:domain blocks) (:objects {names}) (:init (handempty) {init}) "
                       f"(:goal (and (on b0 b1))))")
    code, out, err = main(["plan", "--problem", str(problem)]), *capsys.readouterr()
    assert code == 2 and out == "" and f"at most {stated}" in err
    with pytest.raises(SystemExit) as caught:
        main(["problems", "--blocks", str(MAX_DRAWN_BLOCKS + 1), "--out", str(tmp_path / "p")])
    assert caught.value.code == 2 and drawn in capsys.readouterr().err
