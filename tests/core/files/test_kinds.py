"""A rule file's kind is told in one place, from one read: format, meta.form, npz header, manifest."""

import os

import pytest

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.files import kinds
from csql_sim.core.files.kinds import read_rule_file
from csql_sim.core.files.rulebase import RuleBase, RuleBaseError, save
from csql_sim.core.state.goal_message import GoalForm
from csql_sim.core.state.message import action_messages, format_state_message
from csql_sim.core.state.world import BlocksWorld

FORM_ANY = "S" + "#" * 14 + "G" + "#" * 25


def _index_form() -> RuleBase:
    world = BlocksWorld.of(3)
    return RuleBase(3, [QClassifier(format_state_message(world.states[0], 1), action_messages(3)[0])])


def _goal_form() -> RuleBase:
    return RuleBase(3, [QClassifier(FORM_ANY, action_messages(3)[0])], GoalForm(3).meta())


@pytest.mark.parametrize(("name", "rulebase", "kind"), [
    ("r.yaml", _index_form, kinds.GROUND_YAML), ("g.yaml", _goal_form, kinds.GOAL_YAML),
    ("r.npz", _index_form, kinds.GROUND_NPZ), ("g.npz", _goal_form, kinds.GOAL_NPZ),
])
def test_rule_bases_are_told_by_their_form(tmp_path, name, rulebase, kind):
    path = save(tmp_path / name, rulebase())
    found = read_rule_file(path)
    assert found.kind == kind and found.source == os.fspath(path)
    if kind in (kinds.GROUND_NPZ, kinds.GOAL_NPZ):
        assert found.content() == path.read_bytes()
    else:
        assert found.text() == path.read_text()


def test_the_content_decides_not_the_name(tmp_path):
    npz = save(tmp_path / "g.npz", _goal_form())
    renamed = npz.rename(tmp_path / "g.rules")  # a zip file's header says what it is
    assert read_rule_file(renamed).kind == kinds.GOAL_NPZ
    lifted = tmp_path / "l.yaml"
    lifted.write_text('{"format": "csql-sim lifted q-classifiers", "version": 1}')
    assert read_rule_file(lifted).kind == kinds.LIFTED


def test_a_directory_is_a_sharded_rule_base_when_it_holds_a_manifest(tmp_path):
    (tmp_path / "manifest.json").write_text("{}")  # its fields are the sharded loader's to check
    assert read_rule_file(tmp_path).kind == kinds.SHARDED
    (tmp_path / "manifest.json").unlink()
    with pytest.raises(RuleBaseError, match="a folder, not a regular rule file$"):
        read_rule_file(tmp_path)


def test_problems_are_one_line_each(tmp_path):
    with pytest.raises(RuleBaseError, match=r"absent.yaml: no such rule file$"):
        read_rule_file(tmp_path / "absent.yaml")
    other = tmp_path / "lifted_rules.json"
    other.write_text('{"format": "csql-sim lifted rules", "version": 1}')
    with pytest.raises(RuleBaseError, match="is a csql-sim lifted rules file, not a single ground rule file"):
        read_rule_file(other)
    big = tmp_path / "big.json"
    big.write_text('{"format": "csql-sim lifted q-classifiers", "pad": "' + "x" * (1 << 20) + '"}')
    found = read_rule_file(big)  # told as lifted; its loader names the problem
    assert found.kind == kinds.LIFTED
    with pytest.raises(RuleBaseError, match="above the 1,048,576-byte limit for a lifted Q-classifier file$"):
        found.text()
    latin = tmp_path / "latin1.yaml"
    latin.write_bytes(b"format: csql-sim rule base\nmeta: {seed: \xe9}\n")
    with pytest.raises(RuleBaseError, match=r"latin1.yaml: not UTF-8 text \(byte 40\)$"):
        read_rule_file(latin).text()
