import pytest

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.files.rulebase import RuleBase, RuleBaseError, load, loads, save


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
    assert text.startswith("format: csql-sim rule base\nversion: 2\n")
    assert f"\ncount: {len(_sample().classifiers)}\n" in text
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
        ("format: other\nversion: 2", "not a csql-sim rule base"),
        ("format: csql-sim rule base\nversion: 9\nblocks: 3\nclassifiers: []", "version 9"),
        ("format: csql-sim rule base\nversion: 2\nblocks: 8\ncount: 0\nclassifiers: []", "'blocks'"),
        ("format: csql-sim rule base\nversion: 2\nblocks: 3\ncount: 1\nclassifiers: [{kind: X}]", "kind must be"),
        ("format: csql-sim rule base\nversion: 2\nblocks: 3\ncount: 1\n"
         "classifiers: [{kind: R, condition: S1, action: S}]",
         "16-character"),
        ("format: [unclosed", "not valid YAML"),
    ],
)
def test_foreign_or_corrupt(text, fragment):
    with pytest.raises(RuleBaseError, match=fragment):
        loads(text)


def test_q_fields_required():
    text = (
        "format: csql-sim rule base\nversion: 2\nblocks: 3\ncount: 1\n"
        "classifiers: [{kind: Q, condition: S0111000ttt0000C, action: A70000001000at00, q: 0.5}]"
    )
    with pytest.raises(RuleBaseError, match="strength must be a number"):
        loads(text)


HEADER = "format: csql-sim rule base\nversion: 2\nblocks: 3\ncount: 1\n"
Q_ROW = "{kind: Q, condition: S0111000ttt0000C, action: A70000001000at00, q: %s, strength: %s, age: 1, error: %s}"


def test_cut_at_a_line_boundary_is_refused(tmp_path):
    path = save(tmp_path / "rules.yaml", _sample())
    lines = path.read_text().splitlines(keepends=True)
    path.write_text("".join(lines[:-1]))  # the last classifier's line removed: still valid YAML
    with pytest.raises(RuleBaseError, match=f"holds {len(_sample().classifiers) - 1} classifiers but its header "
                                            f"says {len(_sample().classifiers)}"):
        load(path)


def test_version_1_is_refused_because_a_cut_cannot_be_seen():
    with pytest.raises(RuleBaseError, match="version 1 rule files record no classifier count"):
        loads("format: csql-sim rule base\nversion: 1\nblocks: 3\nclassifiers: []")


@pytest.mark.parametrize(("q", "strength", "error", "fragment"), [
    (".nan", "1", "0", "q must be finite"),
    ("0.5", ".inf", "0", "strength must be finite"),
    ("0.5", "1", "-.inf", "error must be finite"),
    ("0.5", "1", "-0.1", "error must be >= 0"),
])
def test_non_finite_numbers_are_refused(q, strength, error, fragment):
    with pytest.raises(RuleBaseError, match=fragment):
        loads(HEADER + "classifiers: [" + Q_ROW % (q, strength, error) + "]")


def test_a_3_block_file_relabelled_as_2_blocks_is_refused(tmp_path):
    path = save(tmp_path / "rules.yaml", _sample())
    path.write_text(path.read_text().replace("\nblocks: 3\n", "\nblocks: 2\n"))
    with pytest.raises(RuleBaseError, match="classifier 2: condition .* names block C, but the file is for 2 blocks"):
        load(path)


def test_a_relabelled_q_classifier_is_refused():
    text = HEADER.replace("blocks: 3", "blocks: 2") + "classifiers: [" + Q_ROW % (0.5, 1, 0) + "]"
    with pytest.raises(RuleBaseError, match="classifier 1: not a 2-block message"):
        loads(text)


@pytest.mark.parametrize("where", ["blocks", "condition"])
def test_yaml_aliases_are_refused_fast(where):
    laughs = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"{chr(98 + k)}: &{chr(98 + k)} [{', '.join(['*' + chr(97 + k)] * 9)}]\n" for k in range(8))
    if where == "blocks":
        text = laughs + HEADER.replace("blocks: 3", "blocks: *i") + "classifiers: []"
    else:
        text = HEADER + laughs + "classifiers: [{kind: R, condition: *i, action: A70000001000at00}]"
    with pytest.raises(RuleBaseError, match=r"YAML aliases \(\*a\) are not allowed"):
        loads(text)


@pytest.mark.parametrize("depth", [33, 40, 1000])
def test_deep_nesting_is_refused_in_one_line_naming_the_source(depth):
    """Refused whoever notices first (our 32-level check, or a PyYAML that limits depth itself)."""
    text = HEADER + "meta: " + "[" * depth + "]" * depth + "\nclassifiers: []"
    with pytest.raises(RuleBaseError) as refused:
        loads(text, source="deep.yaml")
    assert str(refused.value).startswith("deep.yaml: ") and "\n" not in str(refused.value)


def test_our_nesting_check_counts_levels():
    """The 32-level limit itself, on a depth every YAML parser accepts."""
    from csql_sim.infra.files import InputFileError, load_yaml

    inner = load_yaml("[" * 32 + "]" * 32, "ok.yaml")
    for _ in range(31):
        inner = inner[0]
    assert inner == []
    with pytest.raises(InputFileError, match="deep.yaml: YAML nested deeper than 32 levels"):
        load_yaml("[" * 33 + "]" * 33, "deep.yaml")


def test_only_regular_files_are_read(tmp_path):
    with pytest.raises(RuleBaseError, match="/dev/zero: a device, pipe or socket, not a regular rule file"):
        load("/dev/zero")
    with pytest.raises(RuleBaseError, match="a folder, not a regular rule file"):
        load(tmp_path)


def test_a_huge_file_is_refused_before_reading(tmp_path, monkeypatch):
    import os

    path = tmp_path / "big.yaml"
    with open(path, "wb") as fh:
        fh.truncate(50 * 1024 * 1024)  # a 50 MB (sparse) file
    reads = []  # every read of a rule file goes through a file object os.fdopen makes
    fdopen = os.fdopen
    with monkeypatch.context() as m:
        m.setattr(os, "fdopen", lambda *a, **k: reads.append(a) or fdopen(*a, **k))
        with pytest.raises(RuleBaseError, match="above the 16,777,216-byte limit"):
            load(path)
    assert reads == []  # refused from its size: not one byte was read


def test_wrong_block_count_refused_from_the_header(tmp_path):
    rb = RuleBase(blocks=4, classifiers=list(r_classifiers(4)), meta={"method": "cs-ql"})
    path = save(tmp_path / "four.yaml", rb)
    # corrupt the classifier list: only a header-first check can still name the block count
    path.write_text(path.read_text() + "- {kind: R, condition: [unclosed\n")
    with pytest.raises(RuleBaseError, match="is for 4 blocks, not 3"):
        load(path, blocks=3)
    with pytest.raises(RuleBaseError, match="not valid YAML at line"):
        load(path)


def test_chunked_parse_equals_one_parse(tmp_path, monkeypatch):
    import yaml

    import csql_sim.core.files.rulebase_yaml as rulebase_yaml

    monkeypatch.setattr(rulebase_yaml, "CHUNK_ROWS", 7)
    path = save(tmp_path / "rules.yaml", _sample())
    back = load(path, blocks=3, progress=True)
    rows = yaml.safe_load(path.read_text())["classifiers"]
    assert [(c.kind, c.condition, c.action) for c in back.classifiers] == [
        (r["kind"], r["condition"], r["action"]) for r in rows]
    assert len(back.classifiers) == 37


def test_save_names_its_arguments(tmp_path):
    rb = _sample()
    assert load(save(path=tmp_path / "k.yaml", rulebase=rb)).blocks == 3
    with pytest.raises(TypeError, match="swapped"):
        save(rb, tmp_path / "x.yaml")


def test_the_yaml_text_is_the_same_with_or_without_libyaml(monkeypatch):
    """dumps uses libyaml's emitter where PyYAML has it: the text must be the pure-Python emitter's."""
    from importlib.resources import files

    import yaml

    from csql_sim.core.files import rulebase_yaml

    sample = _sample()
    sample.meta.update(note="é 'quoted' \"double\" # not a comment", nested={"a": [1, 2.5, None, True]})
    shipped = load(files("csql_sim.assets") / "rules" / "blocks3.yaml")
    fast = [rulebase_yaml.dumps(rb) for rb in (sample, shipped)]
    monkeypatch.setattr(rulebase_yaml, "_DUMPER", yaml.SafeDumper)
    assert [rulebase_yaml.dumps(rb) for rb in (sample, shipped)] == fast
    assert loads(fast[0]).meta == sample.meta and len(loads(fast[1]).classifiers) == len(shipped.classifiers)
