"""Hostile rule files through the Python API: every reader refuses them with one RuleBaseError line.

The findings of a hostile-input sweep: integers too large for a float, meta that is not
JSON data, non-ASCII characters and patterns outside the message grammar (YAML and npz),
an npz header nested without bound. The one rule check is
:func:`csql_sim.core.classifiers.r_classifier.validate_r_classifier`.
"""

import io
import json

import numpy as np
import pytest

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import (
    AddDeleteRule,
    PreconditionRule,
    RuleError,
    generate_rules,
    load_paper_rules,
    r_classifier_problem,
    r_classifiers,
    validate_r_classifier,
)
from csql_sim.core.files.pddl_export import domain_text
from csql_sim.core.files.rulebase import RuleBase, RuleBaseError, load, load_r_classifiers, loads, save
from csql_sim.core.files.rulebase_npz import MAX_HEADER_CHARS
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.policies.greedy_table import GreedyTable

BIG = "1" + "0" * 400  # a 401-digit integer: YAML builds it, float() cannot
HEADER = "format: csql-sim rule base\nversion: 2\nblocks: 3\ncount: 1\n"
Q_ROW = "{kind: Q, condition: S0111000ttt0000C, action: A70000001000at00, q: %s, strength: 1, age: %s, error: 0}"


def _refused(path, fragment=""):
    """``load(path)`` raises one RuleBaseError line naming the file (and ``fragment``)."""
    with pytest.raises(RuleBaseError) as info:
        load(path)
    text = str(info.value)
    assert str(path) in text and "\n" not in text and fragment in text, text
    return text


def _sample() -> RuleBase:
    cls = [*r_classifiers(3), QClassifier("S0111000ttt0000C", "A70000001000at00", q=0.5, strength=0.9, age=1.0)]
    return RuleBase(blocks=3, classifiers=cls, meta={"method": "cs-ql", "seed": 4})


def _npz_arrays(tmp_path):
    path = save(tmp_path / "ok.npz", _sample())
    with np.load(path) as z:
        return {k: z[k].copy() for k in z.files}


def _write_npz(path, arrays):
    out = io.BytesIO()
    np.savez_compressed(out, **arrays)
    path.write_bytes(out.getvalue())
    return path


# ------------------------------------------------------------------ 1. huge integers
@pytest.mark.parametrize(("q", "age", "name"), [(BIG, "1", "q"), ("0.5", BIG, "age"), ("-" + BIG, "1", "q")])
def test_an_integer_too_large_for_a_float_is_refused(tmp_path, q, age, name):
    path = tmp_path / "big.yaml"
    path.write_text(HEADER + "classifiers: [" + Q_ROW % (q, age) + "]\n")
    _refused(path, f"{name} must be a finite float64")


def test_a_yaml_integer_beyond_pythons_digit_limit_is_refused(tmp_path):
    path = tmp_path / "huge.yaml"
    path.write_text(HEADER + "classifiers: [" + Q_ROW % ("1" * 5000, "1") + "]\n")
    _refused(path)


# ------------------------------------------------------------------ 2. meta
@pytest.mark.parametrize(("value", "fragment"), [
    ("2024-01-01", "meta.seed is a date"), ("!!binary aGVsbG8=", "meta.seed is a bytes"),
    ("!!set {a, b}", "meta.seed is a set"), (".nan", "meta.seed must be finite"),
    ("[1, {x: .inf}]", "meta.seed[1].x must be finite"), ("{1: a}", "meta.seed has the key 1"),
])
def test_meta_must_be_json_data(tmp_path, value, fragment):
    path = tmp_path / "meta.yaml"
    path.write_text(HEADER.replace("count: 1\n", f"meta:\n  seed: {value}\ncount: 1\n")
                    + "classifiers: [" + Q_ROW % (0.5, 1) + "]\n")
    _refused(path, fragment)


def test_plain_meta_is_kept(tmp_path):
    meta = {"a": [1, 2.5, None, True, "x", {"b": []}], "seed": 2**70}
    for name in ("m.yaml", "m.npz"):
        rb = _sample()
        rb.meta = meta
        assert load(save(tmp_path / name, rb)).meta == meta


def test_npz_meta_with_nan_is_refused(tmp_path):
    arrays = _npz_arrays(tmp_path)
    header = json.loads(str(arrays["header"][()]))
    header["meta"]["seed"] = float("nan")
    arrays["header"] = np.array(json.dumps(header))
    _refused(_write_npz(tmp_path / "nan.npz", arrays), "meta.seed must be finite")


# ------------------------------------------------------------------ 3. non-ASCII
@pytest.mark.parametrize("row", [
    "{kind: R, condition: 'S#1#####b#####é#', action: A10000001000ab00}",
    "{kind: R, condition: 'S#1#####b#####0#', action: A10000001000ab0é}",
    "{kind: Q, condition: S0111000ttt0000ı, action: A70000001000at00, q: 0, strength: 1, age: 0, error: 0}",
])
def test_non_ascii_in_yaml_is_refused(tmp_path, row):
    path = tmp_path / "u.yaml"
    path.write_text(HEADER + f"classifiers: [{row}]\n", encoding="utf-8")
    _refused(path, "not a message character")


@pytest.mark.parametrize(("array", "byte"), [("condition", 0xC3), ("action", 0xE9), ("condition", 0)])
def test_non_ascii_or_nul_in_npz_is_refused(tmp_path, array, byte):
    arrays = _npz_arrays(tmp_path)
    raw = bytearray(arrays[array][0])
    raw[5] = byte  # a NUL in the middle; numpy would strip one at the end into a short string
    arrays[array][0] = bytes(raw)
    path = _write_npz(tmp_path / "u.npz", arrays)
    _refused(path, "not a message character")
    with pytest.raises(RuleBaseError):
        GreedyTable.load(path)  # plan and evaluate read npz arrays directly


# ------------------------------------------------------------------ 4. the message grammar
INVALID = [  # (condition, posted, fragment): each was accepted before, most by every reader but pddl
    ("S#1#####z#####0#", "A10000001000ab00", "position 8 is 'z'"),
    ("S#1#####d#####0#", "A10000001000ab00", "names block D"),
    ("S#1#####b#####0#", "A10000001000a#00", "not a 3-block action message"),
    ("S#1#####b#####0#", "A10000001000ac00", "not a 3-block action message"),
    ("S1##############", "S001####a#####a#", "puts block A on itself"),
    ("S1##############", "S001####0#####b#", "block A is held (on field 0), but the hand field is 'b'"),
    ("S3##############", "S001####0#####a#", "after unstack(B,A) the hand"),
    ("S1##############", "S011####0#####a#", "a held block is marked clear"),
    ("S1##############", "S101####0#####a#", "action slot must be reset"),
    ("S###############", "S001####0#####a#", "action slot must hold one action code"),
    ("S#######ba#####0", "A10000001000ab00", "cycle"),
    ("S##1####b######0", "A10000001000ab00", "which is marked clear"),
    ("S#######00######", "A10000001000ab00", "both held"),
    ("SJ##############", "S001####0#####a#", "action code J is beyond"),
    ("S#1#####b#####0M", "A10000001000ab00", "goal code M is beyond"),
    ("S#1#####b#####0#", "X10000001000ab00", "neither an action message"),
]


@pytest.mark.parametrize(("condition", "posted", "fragment"), INVALID)
def test_invalid_patterns_are_refused_by_every_reader(tmp_path, condition, posted, fragment):
    assert fragment in (r_classifier_problem(condition, posted, 3) or "")
    row = f"{{kind: R, condition: '{condition}', action: '{posted}'}}"
    path = tmp_path / "bad.yaml"
    path.write_text(HEADER + f"classifiers: [{row}]\n")
    _refused(path, fragment)
    arrays = _npz_arrays_of(RuleBase(blocks=3, classifiers=[PreconditionRule("S#1#####b#####0#", "A10000001000ab00")]))
    arrays["condition"][0], arrays["action"][0] = condition.encode(), posted.encode()
    _refused(_write_npz(tmp_path / "bad.npz", arrays), fragment)
    if posted[0] in "AS":
        rule = PreconditionRule(condition, posted) if posted[0] == "A" else AddDeleteRule(condition, posted)
        with pytest.raises(RuleError, match="position|action|output|condition"):
            WorldModel([rule], 3)
        with pytest.raises(RuleError):
            domain_text([rule], 3)


def _npz_arrays_of(rb: RuleBase) -> dict:
    from csql_sim.core.files.rulebase_npz import to_bytes

    with np.load(io.BytesIO(to_bytes(rb))) as z:
        return {k: z[k].copy() for k in z.files}


@pytest.mark.parametrize("n", [2, 3, 4, 5, 6])
def test_the_papers_and_the_generated_rules_are_valid(n):
    rules = [*generate_rules(n), *(load_paper_rules() if n == 3 else ())]
    for rule in rules:
        validate_r_classifier(rule, n)
    WorldModel(rules, n)


def test_discovered_rules_are_valid(tmp_path):
    from csql_sim.jobs.discover import discover

    rules = discover(3, "symbolic", seed=7).rules
    for rule in rules:
        validate_r_classifier(rule, 3)
    path = save(tmp_path / "d.yaml", RuleBase(blocks=3, classifiers=list(rules)))
    assert load_r_classifiers(path, 3).classifiers == list(rules)


def test_rules_that_read_the_goal_field_stay_valid():
    validate_r_classifier(AddDeleteRule("S7#############C", "S00#####0#####a#"), 3)
    assert r_classifier_problem("S7#############C", "S00#####0#####a#", 3) is None


# ------------------------------------------------------------------ 5. npz header
def test_a_deeply_nested_npz_header_is_refused(tmp_path):
    arrays = _npz_arrays(tmp_path)
    text = str(arrays["header"][()])
    arrays["header"] = np.array(text[:-1] + ', "x": ' + "[" * 100_000 + "]" * 100_000 + "}")
    _refused(_write_npz(tmp_path / "deep.npz", arrays), "deeper than")


def test_an_oversized_npz_header_is_refused(tmp_path):
    arrays = _npz_arrays(tmp_path)
    text = str(arrays["header"][()])
    arrays["header"] = np.array(text[:-1] + ', "x": "' + "a" * MAX_HEADER_CHARS + '"}')
    _refused(_write_npz(tmp_path / "long.npz", arrays), "character limit")


def test_brackets_inside_header_strings_do_not_count(tmp_path):
    rb = _sample()
    rb.meta = {"note": "[" * 100 + "{" * 100 + '"\\'}
    assert load(save(tmp_path / "b.npz", rb)).meta == rb.meta


def test_loads_names_its_source():
    with pytest.raises(RuleBaseError, match="^src: classifier 1: q must be a finite float64"):
        loads(HEADER + "classifiers: [" + Q_ROW % (BIG, 1) + "]\n", source="src")
