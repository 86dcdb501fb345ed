import json

import numpy as np

from csql_sim.cli import main
from csql_sim.core.classifiers.lifted_rule import BLOCKS_WORLD, load_lifted
from csql_sim.core.model.world_model import WorldModel


def test_discover_writes_the_lifted_rules_beside_the_rule_file(tmp_path, capsys):
    out, lifted, rep = tmp_path / "rules.yaml", tmp_path / "lifted.json", tmp_path / "r.json"
    args = ["discover", "--world", "symbolic", "--seed", "2", "--quiet", "--out", str(out), "--lifted", str(lifted)]
    assert main([*args, "--json", str(rep)]) == 0
    rules = load_lifted(lifted)
    assert rules == BLOCKS_WORLD
    assert np.array_equal(WorldModel.from_lifted(rules, 4).table.next_state, WorldModel.for_blocks(4).table.next_state)
    report = json.loads(rep.read_text())
    assert report["lifted"] == [r.text() for r in BLOCKS_WORLD] and report["written"] == [str(out), str(lifted)]
    assert json.loads(lifted.read_text())["meta"]["induced_from_blocks"] == 3
    assert main([*args, "--overwrite"]) == 0  # an existing lifted file of ours is replaced when asked
    assert "8 lifted rules" in capsys.readouterr().out


def test_lifted_needs_three_blocks_and_a_writable_path(tmp_path, capsys):
    base = ["discover", "--world", "symbolic", "--quiet", "--out", str(tmp_path / "r.yaml")]
    assert main([*base, "--blocks", "2", "--lifted", str(tmp_path / "l.json")]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert main([*base, "--lifted", str(tmp_path)]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert not (tmp_path / "r.yaml").exists()


def test_two_block_discovery_reports_no_lifted_rules(tmp_path, capsys):
    args = ["discover", "--world", "symbolic", "--blocks", "2", "--quiet", "--out", str(tmp_path / "r.yaml"), "--json"]
    assert main(args) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["lifted"] is None and report["rules"] == 16
