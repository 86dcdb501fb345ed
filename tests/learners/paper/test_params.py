import dataclasses

import pytest

from csql_sim.learners.paper.params import CSQLParams, ParamsError, TabularParams, load_params, resolve_params
from csql_sim.learners.training.tabular import make_learner


def test_defaults_are_frozen_and_paper_values():
    p = CSQLParams()
    assert (p.gamma, p.payoff, p.error_increment) == (0.95, 1.0, 0.0002)
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.gamma = 0.9  # type: ignore[misc]


def test_temperature_schedule_decays_to_floor():
    p = CSQLParams()
    assert p.temperature(0) == p.t0
    assert p.temperature(1) < p.temperature(0)
    assert p.temperature(10**6) == p.t_min


def test_yaml_overrides_flat_and_per_method(tmp_path):
    flat = tmp_path / "flat.yaml"
    flat.write_text("eta: 0.25\nsweep: false\n")
    p = load_params(flat, "cs-ql")
    assert p.eta == 0.25 and p.sweep is False
    nested = tmp_path / "nested.yaml"
    nested.write_text("cs-ql: {eta: 0.3}\ncs-bb-rw: {bid: 0.1}\n")
    assert load_params(nested, "cs-ql").eta == 0.3
    assert load_params(nested, "cs-bb-rw").bid == 0.1


@pytest.mark.parametrize(
    "text, fragment",
    [("etta: 0.3\n", "unknown parameter 'etta'"), ("eta: fast\n", "eta must be float"),
     ("step_cap: 1.5\n", "step_cap must be int"), ("- 1\n", "expected a mapping"),
     ("cs-ql: {}\nxx-ql: {}\n", "unknown method 'xx-ql'")],
)
def test_bad_parameter_files_are_one_line_errors(tmp_path, text, fragment):
    path = tmp_path / "p.yaml"
    path.write_text(text)
    with pytest.raises(ParamsError, match=fragment.replace("(", r"\(")) as info:
        load_params(path, "cs-ql")
    assert "\n" not in str(info.value)


def test_missing_file_and_wrong_dataclass():
    with pytest.raises(ParamsError, match="no such parameter file"):
        load_params("/nonexistent/p.yaml", "cs-ql")
    with pytest.raises(ParamsError, match="needs CSQLParams"):
        resolve_params("cs-ql", TabularParams())
    with pytest.raises(ParamsError, match="unknown method"):
        make_learner("q-magic")


@pytest.mark.parametrize(
    ("text", "fragment"),
    [("gamma: .nan\n", "gamma must be in [0, 1], got nan"), ("gamma: 1.5\n", "gamma must be in [0, 1], got 1.5"),
     ("t0: -0.5\n", "t0 must be > 0, got -0.5"), ("t_min: 0\n", "t_min must be > 0"),
     ("eta: 0\n", "eta must be in (0, 1], got 0.0"), ("eta: 1.01\n", "eta must be in (0, 1]"),
     ("t_decay: 2\n", "t_decay must be in (0, 1], got 2.0"), ("step_cap: 0\n", "step_cap must be >= 1, got 0"),
     ("step_cap: -5\n", "step_cap must be >= 1"), ("age_unit: 0\n", "age_unit must be > 0"),
     ("payoff: .inf\n", "payoff must be a finite number"), ("error_increment: -1\n", "error_increment must be >= 0"),
     ("sweep_passes: -1\n", "sweep_passes must be >= 0"), ("cs-bb-rw: {bid: 0}\ncs-ql: {}\n", None)],
)
def test_out_of_range_parameters_are_refused(tmp_path, text, fragment):
    path = tmp_path / "p.yaml"
    path.write_text(text)
    if fragment is None:  # the bucket-brigade entry is not applied to cs-ql ...
        load_params(path, "cs-ql")
        with pytest.raises(ParamsError, match=r"bid must be in \(0, 1\], got 0"):  # ... but is to cs-bb-rw
            load_params(path, "cs-bb-rw")
        return
    with pytest.raises(ParamsError) as info:
        load_params(path, "cs-ql")
    assert str(info.value) == f"{path}: {fragment}" or str(info.value).startswith(f"{path}: {fragment}")


def test_ranges_are_checked_from_code_too():
    with pytest.raises(ParamsError, match="gamma"):
        CSQLParams(gamma=float("nan"))
    with pytest.raises(ParamsError, match="tax must be in"):
        resolve_params("cs-bb-bz", {"tax": 1.5})


@pytest.mark.parametrize("method", ["lt-ql", "cs-ql", "cs-bb-bz"])
def test_every_parameter_documents_its_range_and_default(method):
    params = resolve_params(method, None)
    docs = " ".join("".join(k.__doc__ or "" for k in type(params).__mro__).split())
    for f in dataclasses.fields(params):
        default = getattr(params, f.name)
        bounds = type(params).bounds(f.name)
        shown = "true" if default is True else f"{default:g}"
        if bounds is None:
            assert f"{f.name}:" in docs and f"default {shown}" in docs
            continue
        # the field's entry, in the nearest class that documents it, names its range and default
        entry = next(d.split(f" {f.name}: ", 1)[1] for k in type(params).__mro__
                     if f" {f.name}: " in (d := " ".join((k.__doc__ or "").split())))
        assert f"Range {bounds}" in entry.split("default", 1)[0]
        assert entry.split("default ", 1)[1].startswith(f"{shown}.")


def test_parameter_files_are_guarded(tmp_path):
    laughs = tmp_path / "laughs.yaml"
    laughs.write_text("a: &a [1, 1, 1, 1]\nb: &b [*a, *a, *a, *a]\neta: *b\n")
    with pytest.raises(ParamsError, match="aliases"):
        load_params(laughs, "cs-ql")
    with pytest.raises(ParamsError, match="not a regular parameter file"):
        load_params("/dev/zero", "cs-ql")


@pytest.mark.parametrize(
    ("overrides", "fragment"),
    [({"bid": 0.0}, r"bid must be in \(0, 1\]"), ({"bid": 1.5}, r"bid must be in \(0, 1\]"),
     ({"tax": -0.1}, r"tax must be in \[0, 1\)"), ({"bid": 0.2, "tax": 0.2}, r"tax must be below bid \(0.2\)"),
     ({"payoff": 0.0}, "payoff must be > 0"), ({"s0": 0.0}, "s0 must be > 0"),
     ({"s0": 2.0}, r"s0 must be at most payoff \(1\), got 2.0")],
)
def test_bucket_brigade_constants_outside_their_ranges_are_rejected(tmp_path, overrides, fragment):
    with pytest.raises(ParamsError, match=fragment):
        resolve_params("cs-bb-rw", overrides)
    path = tmp_path / "p.yaml"
    path.write_text("".join(f"{k}: {v}\n" for k, v in overrides.items()))
    with pytest.raises(ParamsError, match=fragment):
        load_params(path, "cs-bb-bz")
