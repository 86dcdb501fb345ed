"""The paper's statements about Figure 7, checked on a measured :class:`ExperimentResult`.

Section 6 says of Figure 7 (test task, optimal 8 steps):

* the three classifier-system methods start near 150 steps and reach the optimal 8 by
  about trial 700; LT-QL starts near 1400 and reaches 8 by about trial 1150;
* CS-BB-RW reaches 8, then degrades to about 75 steps; CS-BB-BZ does not degrade;
* in (b), CS-QL's value per step rises faster than LT-QL's until about trial 625, the
  bucket-brigade curves rise faster than both, and CS-BB-RW's strength per step later
  falls to intermediate levels.

:func:`evaluate` turns each into a :class:`Statement` (text, whether it holds, the
measured numbers). "Near", "about" and "faster" are the named tolerances below; they
are definitions, chosen once and documented in docs/learning.md, not fitted per run.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from csql_sim.jobs.experiment import ExperimentResult, MethodResult

NEAR_STEPS = 0.5
""""Starts near N steps": the mean steps at trial 0 lie within N * (1 +- NEAR_STEPS).
Trial 0 is a random walk whose steps have a standard deviation about equal to its mean,
so over 50 cycles the mean itself varies by about 15 %."""
REACH_TOLERANCE = 0.0
""""Reaches the optimum": the mean steps over cycles are at most optimal + this."""
ABOUT_TRIALS = 150
""""By about trial K": the first test point at the optimum lies within K +- this."""
RISE_UNTIL = 625
""""Rises faster (early)": compared over the test points in (0, RISE_UNTIL]; the paper
says CS-QL leads LT-QL "until the 625th trial"."""
ABOUT_STEPS = 0.25
""""Degrades to about N steps": the end level lies within N * (1 +- ABOUT_STEPS)."""
END_POINTS = 5
"""The end level of a curve: the mean over its last END_POINTS test points (trials
2300-2500 in the full run), which damps the cycle-to-cycle noise of a single point."""
FALL_MIN = 0.05
""""Falls to intermediate levels": the end value is at least FALL_MIN below the peak of
the value curve and at least half of that peak (a fall, not a collapse)."""

CS_METHODS = ("cs-ql", "cs-bb-bz", "cs-bb-rw")
BB_METHODS = ("cs-bb-bz", "cs-bb-rw")
Q_METHODS = ("lt-ql", "cs-ql")
THREE = "CS-QL, CS-BB-BZ and CS-BB-RW"


@dataclass(frozen=True)
class Statement:
    """One statement of the paper about Figure 7, checked.

    Attributes:
        name: a short key (for tests and scripts).
        text: the statement, in the paper's words where possible.
        holds: whether the measurement satisfies it under the tolerances above.
        measured: the numbers it was judged on.
        paper: the paper's number and the range accepted as "near" / "about" it.

    """

    name: str
    text: str
    holds: bool
    measured: str
    paper: str = ""


def first_reach(r: MethodResult, optimal: int) -> int | None:
    """The first test trial whose mean steps are within :data:`REACH_TOLERANCE` of optimal."""
    for trial, mean in zip(r.trials, r.steps.mean(axis=0), strict=True):
        if mean <= optimal + REACH_TOLERANCE + 1e-9:
            return trial
    return None


def end_steps(r: MethodResult) -> float:
    """The end level of the steps curve (mean over the last :data:`END_POINTS` points)."""
    return float(r.steps.mean(axis=0)[-END_POINTS:].mean())


def end_value(r: MethodResult) -> float:
    """The end level of the value curve (mean over the last :data:`END_POINTS` points)."""
    return float(r.values.mean(axis=0)[-END_POINTS:].mean())


def early_value(r: MethodResult) -> float:
    """The mean value per step over the test points in (0, :data:`RISE_UNTIL`]."""
    trials = np.asarray(r.trials)
    window = (trials > 0) & (trials <= RISE_UNTIL)
    return float(r.values.mean(axis=0)[window].mean()) if window.any() else float("nan")


def _near(x: float, target: float, rel: float) -> bool:
    return abs(x - target) <= rel * target


def _starts_near(rs: list[MethodResult], target: int, subject: str) -> Statement:
    starts = [float(r.steps[:, 0].mean()) for r in rs]
    return Statement(
        f"start-{target}",
        f"{subject} near {target} steps",
        all(_near(s, target, NEAR_STEPS) for s in starts),
        ", ".join(f"{r.method} {s:.0f}" for r, s in zip(rs, starts, strict=True)) + " steps at trial 0",
        f"about {target} (accepted {target * (1 - NEAR_STEPS):.0f}-{target * (1 + NEAR_STEPS):.0f})",
    )


def _reach_by(rs: list[MethodResult], optimal: int, target: int, subject: str) -> Statement:
    firsts = [first_reach(r, optimal) for r in rs]
    return Statement(
        f"optimal-by-{target}",
        f"{subject} the optimal {optimal} steps by about trial {target}",
        all(f is not None and abs(f - target) <= ABOUT_TRIALS for f in firsts),
        "first at the optimum: " + ", ".join(
            f"{r.method} {_when(f, target)}" for r, f in zip(rs, firsts, strict=True)),
        f"about trial {target} (accepted {target - ABOUT_TRIALS}-{target + ABOUT_TRIALS})",
    )


def _when(first: int | None, target: int) -> str:
    """A first trial at the optimum, and how it compares with the paper's."""
    if first is None:
        return "never"
    if abs(first - target) <= ABOUT_TRIALS:
        return f"trial {first}"
    return f"trial {first} ({'earlier' if first < target else 'later'} than the paper)"


def _rises_faster(fast: list[MethodResult], slow: list[MethodResult], name: str, text: str) -> Statement:
    lead = {r.method: early_value(r) for r in fast + slow}
    top = max(lead[r.method] for r in slow)
    return Statement(
        name,
        f"{text} (mean value per step, trials 50-{RISE_UNTIL})",
        all(lead[r.method] > top for r in fast),
        ", ".join(f"{m} {v:.3f}" for m, v in lead.items()),
        "faster (accepted: every faster method's mean above every slower one's)",
    )


def _rw_degrades(rw: MethodResult, optimal: int) -> Statement:
    first, end = first_reach(rw, optimal), end_steps(rw)
    best, last = float(rw.steps.mean(axis=0).min()), float(rw.steps.mean(axis=0)[-1])
    return Statement(
        "rw-degrades-to-75",
        f"CS-BB-RW reaches {optimal} steps, then degrades to about 75",
        first is not None and _near(end, 75, ABOUT_STEPS),
        f"first at {optimal}: {'never' if first is None else f'trial {first}'} (best mean {best:.2f}); end level "
        f"(mean of the last {END_POINTS} test points) {end:.1f}, at the last point {last:.1f}",
        f"about 75 (accepted {75 * (1 - ABOUT_STEPS):.0f}-{75 * (1 + ABOUT_STEPS):.0f}) for the end level",
    )


def _bz_stays(bz: MethodResult, optimal: int) -> Statement:
    end = end_steps(bz)
    return Statement(
        "bz-stays-optimal",
        "CS-BB-BZ does not degrade: it stays at the optimum",
        first_reach(bz, optimal) is not None and end <= optimal + REACH_TOLERANCE + 1e-9,
        f"end level (mean of the last {END_POINTS} test points) {end:.2f}",
        f"stays at {optimal}",
    )


def _rw_value_falls(rw: MethodResult) -> Statement:
    curve = rw.values.mean(axis=0)
    peak, end = float(curve.max()), end_value(rw)
    return Statement(
        "rw-value-falls",
        "CS-BB-RW's strength per step then falls to intermediate levels",
        end <= peak - FALL_MIN and end >= peak / 2,
        f"peak {peak:.3f} at trial {rw.trials[int(curve.argmax())]}, end level {end:.3f}",
        f"a fall of at least {FALL_MIN} from the peak, to no less than half of it",
    )


def evaluate(result: ExperimentResult) -> list[Statement]:
    """Every statement whose methods are all in ``result``, in the paper's order."""
    by = {r.method: r for r in result.methods}
    opt = result.optimal

    def have(*methods: str) -> bool:
        return all(m in by for m in methods)

    def rs(methods: tuple[str, ...]) -> list[MethodResult]:
        return [by[m] for m in methods]

    checks: list[tuple[tuple[str, ...], Callable[[], Statement]]] = [
        (CS_METHODS, lambda: _starts_near(rs(CS_METHODS), 150, f"{THREE} start")),
        (CS_METHODS, lambda: _reach_by(rs(CS_METHODS), opt, 700, f"{THREE} reach")),
        (("lt-ql",), lambda: _starts_near(rs(("lt-ql",)), 1400, "LT-QL starts")),
        (("lt-ql",), lambda: _reach_by(rs(("lt-ql",)), opt, 1150, "LT-QL reaches")),
        (("cs-bb-rw",), lambda: _rw_degrades(by["cs-bb-rw"], opt)),
        (("cs-bb-bz",), lambda: _bz_stays(by["cs-bb-bz"], opt)),
        (Q_METHODS, lambda: _rises_faster(
            rs(("cs-ql",)), rs(("lt-ql",)), "b-csql-faster", "(b) CS-QL rises faster than LT-QL early")),
        (BB_METHODS + Q_METHODS, lambda: _rises_faster(
            rs(BB_METHODS), rs(Q_METHODS), "b-bb-faster", "(b) CS-BB-BZ and CS-BB-RW rise faster than both")),
        (("cs-bb-rw",), lambda: _rw_value_falls(by["cs-bb-rw"])),
    ]
    return [make() for methods, make in checks if have(*methods)]


def statement_lines(statements: list[Statement]) -> list[str]:
    """One line per statement: holds / does not hold, the statement, what the paper says, what was measured."""
    return [f"{'holds        ' if s.holds else 'does not hold'}  {s.text}: paper {s.paper}; measured {s.measured}"
            for s in statements]
