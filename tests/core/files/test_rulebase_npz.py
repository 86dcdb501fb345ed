import numpy as np
import pytest

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.files.rulebase import RuleBase, RuleBaseError, dumps, load, loads, save
from csql_sim.learners.training.tabular import train


def _fields(rb: RuleBase) -> list[tuple]:
    return [(c.kind, c.condition, c.action, *((c.q, c.strength, c.age, c.error) if c.kind == "Q" else ()))
            for c in rb.classifiers]


@pytest.fixture(scope="module")
def trained() -> RuleBase:
    return train("cs-ql", 300, seed=2, params={"sweep": False})


def test_npz_round_trip_equals_yaml(tmp_path, trained):
    npz = save(tmp_path / "r.npz", trained)
    yml = save(tmp_path / "r.yaml", trained)
    back_npz, back_yaml = load(npz), load(yml)
    assert npz.read_bytes()[:2] == b"PK"  # a zip archive, not YAML text
    assert back_npz.blocks == 3 and back_npz.meta == trained.meta
    assert _fields(back_npz) == _fields(trained)  # full float64 values
    assert dumps(back_npz) == dumps(back_yaml) == dumps(trained)
    assert npz.stat().st_size < yml.stat().st_size / 4


def test_npz_cut_anywhere_is_refused(tmp_path, trained):
    data = save(tmp_path / "r.npz", trained).read_bytes()
    cut = tmp_path / "cut.npz"
    for end in sorted({0, 1, 30, len(data) // 3, len(data) // 2, len(data) - 200, len(data) - 22, len(data) - 1}):
        cut.write_bytes(data[:end])
        with pytest.raises(RuleBaseError):
            load(cut)


def test_npz_count_must_match(tmp_path, trained):
    path = save(tmp_path / "r.npz", trained)
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["q"] = arrays["q"][:-1]
    np.savez_compressed(tmp_path / "short.npz", **arrays)
    with pytest.raises(RuleBaseError, match="header says"):
        load(tmp_path / "short.npz")
    np.savez_compressed(tmp_path / "foreign.npz", x=np.zeros(3))
    with pytest.raises(RuleBaseError, match="not a csql-sim npz rule base"):
        load(tmp_path / "foreign.npz")


def test_yaml_cut_at_any_line_boundary_is_refused(tmp_path):
    rb = RuleBase(blocks=3, classifiers=[*r_classifiers(3)[:5],
        QClassifier("S0111000ttt0000C", "A70000001000at00", q=0.5, strength=0.9, age=1.0, error=0.1)])
    lines = dumps(rb).splitlines(keepends=True)
    assert loads("".join(lines)).classifiers
    for end in range(len(lines)):
        with pytest.raises(RuleBaseError):
            loads("".join(lines[:end]))


def test_npz_with_a_foreign_message_is_refused(tmp_path, trained):
    path = save(tmp_path / "r.npz", trained)
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["condition"] = arrays["condition"].copy()
    arrays["condition"][-1] = b"S0111000tdt0000C"  # block D in a 3-block file
    np.savez_compressed(tmp_path / "bad.npz", **arrays)
    with pytest.raises(RuleBaseError, match="classifier"):
        load(tmp_path / "bad.npz")
    arrays["condition"] = np.load(path)["condition"]
    arrays["error"] = arrays["error"].copy()
    arrays["error"][0] = np.nan
    np.savez_compressed(tmp_path / "nan.npz", **arrays)
    with pytest.raises(RuleBaseError, match="finite"):
        load(tmp_path / "nan.npz")
