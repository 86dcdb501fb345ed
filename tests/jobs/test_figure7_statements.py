import numpy as np
import pytest

from csql_sim.jobs.experiment import ExperimentResult, MethodResult, run_experiment
from csql_sim.jobs.figure7_statements import (
    ABOUT_TRIALS,
    END_POINTS,
    Statement,
    end_steps,
    evaluate,
    first_reach,
    statement_lines,
)

TRIALS = tuple(range(0, 2501, 50))


def method(name: str, steps: list[float], values: list[float]) -> MethodResult:
    """A two-cycle result whose mean curves are ``steps`` and ``values``."""
    s, v = np.array(steps, dtype=float), np.array(values, dtype=float)
    return MethodResult(name, TRIALS, np.stack([s - 1, s + 1]), np.stack([v, v]))


def falling(start: float, reach: int, end: float = 8.0) -> list[float]:
    """Steps falling geometrically from ``start`` to 8 at trial ``reach``, then ``end``."""
    out = []
    for t in TRIALS:
        out.append(8 * (start / 8) ** (1 - t / reach) if t < reach else (8.0 if t < 1000 else end))
    return out


def rising(rate: float, top: float) -> list[float]:
    return [top * (1 - np.exp(-rate * t)) for t in TRIALS]


RW_VALUES = [min(0.95, 0.004 * t) if t < 1000 else 0.7 for t in TRIALS]


def paper_like(**changes: MethodResult) -> ExperimentResult:
    methods = {
        "lt-ql": method("lt-ql", falling(1400, 1150), rising(0.002, 0.84)),
        "cs-ql": method("cs-ql", falling(150, 700), rising(0.005, 0.84)),
        "cs-bb-bz": method("cs-bb-bz", falling(150, 700), rising(0.01, 1.0)),
        "cs-bb-rw": method("cs-bb-rw", falling(150, 700, end=75.0), RW_VALUES),
    }
    methods.update(changes)
    return ExperimentResult(tuple(methods.values()), 2, 2500, 0, 8)


def by_name(statements: list[Statement]) -> dict[str, Statement]:
    return {s.name: s for s in statements}


def test_curves_shaped_like_the_papers_satisfy_every_statement():
    statements = evaluate(paper_like())
    assert len(statements) == 9
    assert [s.name for s in statements if not s.holds] == []
    lines = statement_lines(statements)
    assert all(line.startswith("holds") for line in lines)
    assert "cs-bb-rw trial 700" in by_name(statements)["optimal-by-700"].measured


@pytest.mark.parametrize(
    "change, broken",
    [
        ({"cs-ql": method("cs-ql", falling(400, 700), rising(0.005, 0.84))}, "start-150"),
        ({"cs-bb-bz": method("cs-bb-bz", falling(150, 700 + ABOUT_TRIALS + 50), rising(0.01, 1.0))}, "optimal-by-700"),
        ({"lt-ql": method("lt-ql", falling(1400, 700), rising(0.002, 0.84))}, "optimal-by-1150"),
        ({"cs-bb-rw": method("cs-bb-rw", falling(150, 700, end=30.0), RW_VALUES)}, "rw-degrades-to-75"),
        ({"cs-bb-bz": method("cs-bb-bz", falling(150, 700, end=20.0), rising(0.01, 1.0))}, "bz-stays-optimal"),
        ({"cs-ql": method("cs-ql", falling(150, 700), rising(0.001, 0.84))}, "b-csql-faster"),
        ({"cs-bb-bz": method("cs-bb-bz", falling(150, 700), rising(0.002, 1.0))}, "b-bb-faster"),
        ({"cs-bb-rw": method("cs-bb-rw", falling(150, 700, end=75.0), rising(0.01, 1.0))}, "rw-value-falls"),
    ],
)
def test_each_statement_fails_when_its_curve_departs(change, broken):
    failed = [s.name for s in evaluate(paper_like(**change)) if not s.holds]
    assert failed == [broken]


def test_reaching_the_optimum_needs_every_cycle_there():
    steps = np.full((2, len(TRIALS)), 8.0)
    steps[1, :10] = 9.0  # one cycle one step off until trial 450
    r = MethodResult("cs-ql", TRIALS, steps, np.zeros_like(steps))
    assert first_reach(r, 8) == 500


def test_only_statements_about_the_methods_run_are_checked():
    result = paper_like()
    only = ExperimentResult(result.methods[1:2], 2, 2500, 0, 8)
    assert evaluate(only) == []
    two = ExperimentResult(result.methods[:2], 2, 2500, 0, 8)
    assert [s.name for s in evaluate(two)] == ["start-1400", "optimal-by-1150", "b-csql-faster"]


def test_end_level_averages_the_last_points():
    rw = falling(150, 700, end=75.0)
    rw[-1] = 75.0 + 5 * END_POINTS  # one noisy last point moves the end level by 5
    statements = by_name(evaluate(paper_like(**{"cs-bb-rw": method("cs-bb-rw", rw, RW_VALUES)})))
    measured = statements["rw-degrades-to-75"].measured
    assert "end level (mean of the last 5 test points) 80.0" in measured and "at the last point 100.0" in measured


STABLE_AT_20 = (  # "start near" and the first trial at exactly 8 move with the cycle count; not these
    "optimal-by-1150", "bz-stays-optimal", "b-csql-faster", "b-bb-faster", "rw-value-falls")


def test_statements_stable_at_20_cycles_hold_with_the_default_constants():
    """20 cycles x 2500 trials, seed 1 (16 s of CPU: about 8 s on 2 idle cores)."""
    result = run_experiment(cycles=20, trials=2500, seed=1, workers=2)
    got = by_name(evaluate(result))
    for name in STABLE_AT_20:
        assert got[name].holds, f"{got[name].text}: {got[name].measured}"
    rw = next(r for r in result.methods if r.method == "cs-bb-rw")
    assert end_steps(rw) > 5 * result.optimal  # CS-BB-RW degrades (~60-70 here; "about 75" needs 50 cycles)


def test_each_line_says_what_the_paper_says_and_what_was_measured():
    """A statement that does not hold because the optimum came early says so, with the paper's number."""
    from csql_sim.jobs.figure7_statements import Statement, _when, statement_lines

    line = statement_lines([Statement("x", "reach by about trial 700", False, f"cs-ql {_when(300, 700)}",
                                      "about trial 700 (accepted 550-850)")])[0]
    assert line.startswith("does not hold") and "paper about trial 700 (accepted 550-850)" in line
    assert "measured cs-ql trial 300 (earlier than the paper)" in line
