import pytest

from csql_sim.classifiers import Classifier, Q
from csql_sim.rulebase import RuleBase, RuleBaseError, load, loads, save
from csql_sim.rules import r_classifiers


def _sample() -> RuleBase:
    cls = r_classifiers(3)
    cls.append(Classifier(Q, "S0111000ttt0000C", "A70000001000at00", q=0.857373, strength=0.999215,
                          age=3.26719, error=0.000601))
    return RuleBase(blocks=3, classifiers=cls, meta={"method": "cs-ql", "seed": 4})


def test_round_trip(tmp_path):
    path = save(tmp_path / "rules.yaml", _sample())
    back = load(path)
    assert back.blocks == 3 and back.meta == {"method": "cs-ql", "seed": 4}
    got = [(c.kind, c.condition, c.action, c.q, c.strength, c.age, c.error) for c in back.classifiers]
    want = [(c.kind, c.condition, c.action, c.q, c.strength, c.age, c.error) for c in _sample().classifiers]
    assert got == want
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
