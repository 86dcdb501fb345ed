"""A hostile-input sweep through the command line: exit 2, one stderr line naming the file, nothing written.

Each test reproduces one finding (a traceback or a silent acceptance before the fix);
the Python API's side of the same findings is in tests/core/test_hostile_rules.py.
"""

import io
import json
import re

import numpy as np
import pytest

from csql_sim.cli import main
from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.files.rulebase import RuleBase, load, save
from csql_sim.infra.errors import CsqlError
from csql_sim.learners.generalize.pruning import prune
from csql_sim.learners.paper.params import ParamsError, load_params, resolve_params

BIG = "1" + "0" * 400  # a 401-digit integer


def refused(capsys, tmp_path, *argv, names):
    """Run a command that must be refused: status 2, one stderr line naming ``names``, no new file."""
    before = set(tmp_path.rglob("*"))
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert code == 2, err
    assert err.count("\n") == 1 and re.match(r"csql-sim [a-z-]+: error: ", err) and "Traceback" not in err, err
    assert str(names) in err, err
    assert set(tmp_path.rglob("*")) == before  # nothing written
    return err


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """A small trained 3-block rule file (R- and Q-classifiers) as YAML text."""
    path = tmp_path_factory.mktemp("rules") / "r3.yaml"
    assert main(["train", "--trials", "50", "--out", str(path), "--quiet"]) == 0
    return path.read_text()


def _write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _paper(tmp_path, name, old="", new=""):
    """The paper's 36 rules as a rule file, with ``old`` replaced by ``new`` once."""
    text = save(tmp_path / "paper.src", RuleBase(blocks=3, classifiers=list(r_classifiers(3)))).read_text()
    (tmp_path / "paper.src").unlink()
    assert old in text
    return _write(tmp_path, name, text.replace(old, new, 1))


def _readers(path, out):
    """Every command that reads a rule file, each with the file in its place."""
    return [
        ["show", "--rules", path], ["show", "--rules", path, "--json"],
        ["plan", "--rules", path, "--start", "CBA", "--goal", "BAC"],
        ["prune", "--rules", path, "--threshold", "0.1", "--out", out / "p.yaml"],
        ["evaluate", "--rules", path, "--pairs", "1", "--quiet"],
        ["render", "--rules", path, "--start", "CBA", "--goal", "BAC", "--out", out / "v.mp4"],
    ]


# ------------------------------------------------------------------ 1. huge integers
@pytest.mark.parametrize("field", ["q", "age"])
def test_a_400_digit_number_in_a_rule_file(capsys, tmp_path, trained, field):
    path = _write(tmp_path, "big.yaml", re.sub(rf", {field}: [^,}}]+", f", {field}: {BIG}", trained, count=1))
    for argv in [*_readers(path, tmp_path), ["pddl", "--domain-rules", path, "--out", tmp_path / "pddl"]]:
        refused(capsys, tmp_path, *argv, names=path)
    with pytest.raises(CsqlError, match=f"{field} must be a finite float64"):
        load(path)


@pytest.mark.parametrize(("text", "fragment"), [
    (f"step_cap: {BIG}\n", "step_cap must be at most"), (f"step_cap: -{BIG}\n", "step_cap must be >= 1"),
    (f"gamma: {BIG}\n", "gamma must be a finite float64"), ("step_cap: " + "9" * 5000 + "\n", ""),
    ("sweep_passes: 9223372036854775808\n", "sweep_passes must be at most"),
])
def test_a_huge_integer_in_params(capsys, tmp_path, text, fragment):
    params = _write(tmp_path, "p.yaml", text)
    err = refused(capsys, tmp_path, "train", "--out", tmp_path / "r.yaml", "--params", params, names=params)
    assert fragment in err
    with pytest.raises(ParamsError):
        load_params(params, "cs-ql")
    with pytest.raises(ParamsError, match="step_cap"):
        resolve_params("cs-ql", {"step_cap": 10**400})


# ------------------------------------------------------------------ 2. meta that is not JSON data
@pytest.mark.parametrize(("value", "kind"), [("2024-01-01", "date"), ("!!binary aGVsbG8=", "bytes"),
                                             ("!!set {a, b}", "set")])
def test_meta_that_is_not_json_data(capsys, tmp_path, trained, value, kind):
    path = _write(tmp_path, "meta.yaml", trained.replace("\n  seed: ", f"\n  when: {value}\n  seed: ", 1))
    for argv in (["show", "--rules", path, "--json"],
                 ["prune", "--rules", path, "--threshold", "0.1", "--out", tmp_path / "p.yaml"],
                 ["prune", "--rules", path, "--threshold", "0.1", "--out", tmp_path / "p.npz"]):
        err = refused(capsys, tmp_path, *argv, names=path)
        assert f"meta.when is a {kind}" in err


# ------------------------------------------------------------------ 3. non-ASCII patterns
def test_a_non_ascii_pattern_in_yaml(capsys, tmp_path):
    path = _paper(tmp_path, "u.yaml", "S#1#####b#####0#", "S#1#####b#####é#")
    for argv in [*_readers(path, tmp_path), ["train", "--domain-rules", path, "--out", tmp_path / "t.yaml", "--quiet"],
                 ["pddl", "--domain-rules", path, "--out", tmp_path / "pddl"]]:
        refused(capsys, tmp_path, *argv, names=path)


def test_a_non_ascii_pattern_in_npz(capsys, tmp_path, trained):
    source = load(_write(tmp_path, "t.yaml", trained))
    npz = save(tmp_path / "t.npz", source)
    with np.load(npz) as z:
        arrays = {k: z[k].copy() for k in z.files}
    arrays["condition"][0] = arrays["condition"][0][:14] + b"\xc3" + arrays["condition"][0][15:]
    out = io.BytesIO()
    np.savez_compressed(out, **arrays)
    path = tmp_path / "u.npz"
    path.write_bytes(out.getvalue())
    for argv in _readers(path, tmp_path):
        refused(capsys, tmp_path, *argv, names=path)


# ------------------------------------------------------------------ 4. patterns outside the message grammar
@pytest.mark.parametrize(("old", "new", "fragment"), [
    ("S#1#####b#####0#", "S#1#####z#####0#", "position 8 is 'z'"),  # a letter that is no block
    ("A10000001000ab00", "A10000001000a#00", "not a 3-block action message"),  # '#' in an action message
    ("S001####0#####a#", "S001####a#####a#", "puts block A on itself"),  # add-delete output: A on A
    ("S001####0#####a#", "S001####0#####b#", "the hand field is 'b'"),  # the wrong held block
])
def test_invalid_patterns(capsys, tmp_path, old, new, fragment):
    path = _paper(tmp_path, "bad.yaml", old, new)
    for argv in (["train", "--domain-rules", path, "--out", tmp_path / "t.yaml", "--quiet", "--trials", "5"],
                 ["pddl", "--domain-rules", path, "--out", tmp_path / "pddl"], ["show", "--rules", path],
                 ["plan", "--rules", path, "--start", "CBA", "--goal", "BAC"]):
        err = refused(capsys, tmp_path, *argv, names=path)
        assert fragment in err


def test_discovered_rules_still_train(capsys, tmp_path):
    rules = tmp_path / "d.yaml"
    assert main(["discover", "--world", "symbolic", "--blocks", "3", "--out", str(rules), "--quiet"]) == 0
    assert main(["train", "--domain-rules", str(rules), "--trials", "20", "--out", str(tmp_path / "t.yaml"),
                 "--quiet"]) == 0
    assert main(["show", "--rules", str(tmp_path / "t.yaml")]) == 0


# ------------------------------------------------------------------ 5. a deeply nested npz header
def test_a_deeply_nested_npz_header(capsys, tmp_path, trained):
    npz = save(tmp_path / "t.npz", load(_write(tmp_path, "t.yaml", trained)))
    with np.load(npz) as z:
        arrays = {k: z[k].copy() for k in z.files}
    header = json.dumps(json.loads(str(arrays["header"][()])))
    arrays["header"] = np.array(header[:-1] + ', "x": ' + "[" * 100_000 + "]" * 100_000 + "}")
    out = io.BytesIO()
    np.savez_compressed(out, **arrays)
    path = tmp_path / "deep.npz"
    path.write_bytes(out.getvalue())
    for argv in (["show", "--rules", path], ["plan", "--rules", path, "--pairs", "all"],
                 ["evaluate", "--rules", path, "--pairs", "1"]):
        refused(capsys, tmp_path, *argv, names=path)


# ------------------------------------------------------------------ 6. prune(rb, nan) through the API
@pytest.mark.parametrize("threshold", [float("nan"), float("inf"), -0.1, 1.5, "0.1", True, None])
def test_prune_refuses_what_the_command_line_refuses(trained, tmp_path, threshold):
    rb = load(_write(tmp_path, "t.yaml", trained))
    with pytest.raises(CsqlError, match=r"threshold must be a number in \[0, 1\]"):
        prune(rb, threshold)


def test_prune_keeps_a_plain_float(trained, tmp_path):
    rb = load(_write(tmp_path, "t.yaml", trained))
    pruned = prune(rb, np.float32(0.5))
    assert type(pruned.meta["pruned_at"]) is float
    assert load(save(tmp_path / "p.yaml", pruned)).meta["pruned_at"] == pruned.meta["pruned_at"]


@pytest.mark.parametrize("keep", ["add-delete only", "one of each"])
def test_a_domain_with_dead_end_states_is_refused_before_training(capsys, tmp_path, keep):
    """Valid rules under which some state has no legal action: one line, not an empty-max traceback."""
    from csql_sim.core.classifiers.r_classifier import AddDeleteRule, PreconditionRule

    rules = r_classifiers(3)
    if keep == "add-delete only":
        kept = [r for r in rules if isinstance(r, AddDeleteRule)]
    else:
        kept = [next(r for r in rules if isinstance(r, PreconditionRule)),
                next(r for r in rules if isinstance(r, AddDeleteRule))]
    domain = save(tmp_path / "domain.yaml", RuleBase(3, kept))
    refused(capsys, tmp_path, "train", "--domain-rules", domain, "--out", tmp_path / "t.yaml", names="no legal action")
    assert not (tmp_path / "t.yaml").exists()
