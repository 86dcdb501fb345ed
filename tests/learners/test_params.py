import dataclasses

import pytest

from csql_sim.learners import CSQLParams, ParamsError, load_params, make_learner, resolve_params


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
        resolve_params("cs-ql", load_params.__globals__["TabularParams"]())
    with pytest.raises(ParamsError, match="unknown method"):
        make_learner("q-magic")
