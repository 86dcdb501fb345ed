import pytest

from csql_sim.q_classifier import QClassifier
from csql_sim.r_classifier import r_classifiers
from csql_sim.rulebase import RuleBase, RuleBaseError, load, loads, save


def _sample() -> RuleBase:
    cls = list(r_classifiers(3))
    cls.append(QClassifier("S0111000ttt0000C", "A70000001000at00", q=0.857373, strength=0.999215,
                          age=3.26719, error=0.000601))
    return RuleBase(blocks=3, classifiers=cls, meta={"method": "cs-ql", "seed": 4})


def test_round_trip(tmp_path):
    path = save(tmp_path / "rules.yaml", _sample())
    back = load(path)
    assert back.blocks == 3 and back.meta == {"method": "cs-ql", "seed": 4}
    assert back.classifiers[:36] == _sample().classifiers[:36]  # typed R-classifiers compare by value
    got, want = back.classifiers[36], _sample().classifiers[36]
    assert (got.condition, got.action, got.q, got.strength, got.age, got.error) == (
        want.condition, want.action, want.q, want.strength, want.age, want.error)
    text = path.read_text()
    assert text.startswith("format: csql-sim rule base\nversion: 1\n")
    assert [p.name for p in tmp_path.iterdir()] == ["rules.yaml"]  # no temporary left behind


def test_missing_file(tmp_path):
    with pytest.raises(RuleBaseError, match="no such rule file"):
        load(tmp_path / "nope.yaml")


def test_truncated_file(tmp_path):
    path = save(tmp_path / "rules.yaml", _sample())
    text = path.read_text()
    path.write_text(text[: len(text) - 40])
    with pytest.raises(RuleBaseError):
        load(path)


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("just a string", "not a csql-sim rule base"),
        ("format: other\nversion: 1", "not a csql-sim rule base"),
        ("format: csql-sim rule base\nversion: 9\nblocks: 3\nclassifiers: []", "version 9"),
        ("format: csql-sim rule base\nversion: 1\nblocks: 8\nclassifiers: []", "'blocks'"),
        ("format: csql-sim rule base\nversion: 1\nblocks: 3\nclassifiers: [{kind: X}]", "kind must be"),
        ("format: csql-sim rule base\nversion: 1\nblocks: 3\nclassifiers: [{kind: R, condition: S1, action: S}]",
         "16-character"),
        ("format: [unclosed", "not valid YAML"),
    ],
)
def test_foreign_or_corrupt(text, fragment):
    with pytest.raises(RuleBaseError, match=fragment):
        loads(text)


def test_q_fields_required():
    text = (
        "format: csql-sim rule base\nversion: 1\nblocks: 3\n"
        "classifiers: [{kind: Q, condition: S0111000ttt0000C, action: A70000001000at00, q: 0.5}]"
    )
    with pytest.raises(RuleBaseError, match="strength must be a number"):
        loads(text)
