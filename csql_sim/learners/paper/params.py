"""Learner parameters: one frozen dataclass per learner, overridable from YAML.

Symbols follow the paper: gamma (eq. 2), eta (eq. 1), T (eq. 3). The temperature
schedule is per trial: ``T_k = max(T_min, T0 * decay**k)`` for training trial ``k``.

Every parameter has a range, written next to its default in the class docstring and
checked when the dataclass is built (from code, a dict or a ``--params`` file): a value
outside it, NaN or infinity, a number too large for a float64 or an integer parameter
beyond int64 (:data:`MAX_INT`) is a one-line :class:`ParamsError`.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass, fields
from typing import ClassVar

from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import InputFileError, load_yaml, read_text_file
from csql_sim.learners.paper.params_bounds import (  # re-exported
    AT_LEAST_ONE as AT_LEAST_ONE,
)
from csql_sim.learners.paper.params_bounds import (
    FINITE as FINITE,
)
from csql_sim.learners.paper.params_bounds import (
    NON_NEGATIVE as NON_NEGATIVE,
)
from csql_sim.learners.paper.params_bounds import (
    POSITIVE as POSITIVE,
)
from csql_sim.learners.paper.params_bounds import (
    RATIO as RATIO,
)
from csql_sim.learners.paper.params_bounds import (
    UNIT as UNIT,
)
from csql_sim.learners.paper.params_bounds import (
    UNIT_NO_ZERO as UNIT_NO_ZERO,
)
from csql_sim.learners.paper.params_bounds import (
    Bounds as Bounds,
)

MAX_FILE_BYTES = 1024 * 1024
"""Largest parameter file read."""
MAX_INT = 2**63 - 1  # largest integer parameter (the fast engine's kernels hold them as int64)


class ParamsError(CsqlError):
    """A bad parameter file or value."""


@dataclass(frozen=True)
class CommonParams:
    """Parameters every learner shares (trial structure and temperature schedule).

    Attributes:
        t0: T at trial 0 (eq. 3); Q-values lie in [0, 1], so 0.5 is close to uniform.
            Range > 0; default 0.5.
        t_decay: T shrinks by this factor per training trial. Range (0, 1]; default 0.996.
        t_min: floor of T (near-greedy; keeps exp() finite). Range > 0; default 0.0005.
        step_cap: a trial ends unreached after this many steps. Random walks need 168
            (legal actions) and 1584 (all 18) steps on the test task, so the cap only
            trims the rare very long walks of the first trials. Range >= 1 (an integer, at
            most :data:`MAX_INT`); default 10000.
        age_unit: steps per unit of age. Figure 6's ages (~3.2 after 2500 trials of about
            13 steps) read as 10,000 steps per unit. Range > 0; default 10000.

    """

    RANGES: ClassVar[dict[str, Bounds]] = {
        "t0": POSITIVE, "t_decay": UNIT_NO_ZERO, "t_min": POSITIVE, "step_cap": AT_LEAST_ONE, "age_unit": POSITIVE,
    }

    t0: float = 0.5  # T_0
    t_decay: float = 0.996  # T_{k+1} = T_k * decay
    t_min: float = 0.0005  # T floor
    step_cap: int = 10000  # steps per trial
    age_unit: float = 10000.0  # steps per unit of age (Figure 6)

    def __post_init__(self) -> None:
        """Check every field against its range (see the class docstrings)."""
        for f in fields(self):
            value = getattr(self, f.name)
            bounds = self.bounds(f.name)
            if bounds is None or isinstance(value, bool):
                continue
            if isinstance(value, int) and f.type == "int" and value > MAX_INT:
                raise ParamsError(f"{f.name} must be at most {MAX_INT} (int64), got {_shown(value)}")
            if isinstance(value, (int, float)) and not bounds.contains(value):
                raise ParamsError(f"{f.name} must be {_describe(bounds)}, got {_shown(value)}")

    @classmethod
    def bounds(cls, name: str) -> Bounds | None:
        """The range of parameter ``name`` (None for flags)."""
        for klass in cls.__mro__:
            ranges = klass.__dict__.get("RANGES", {})
            if name in ranges:
                return ranges[name]
        return None

    def temperature(self, trial: int) -> float:
        """T for training trial ``trial`` (eq. 3's T)."""
        return max(self.t_min, self.t0 * self.t_decay**trial)


@dataclass(frozen=True)
class QLearningParams(CommonParams):
    """What the two Q-learners (LT-QL and CS-QL) share: eq. 1, 2 and 4.

    Attributes:
        gamma: discount gamma (eq. 2); Figure 6's Q-values are powers of 0.95.
            Range [0, 1]; default 0.95.
        eta: step size eta (eq. 1). Range (0, 1]; default 0.5.
        payoff: r on reaching the goal (0 otherwise). Range finite; default 1.
        q0: initial Q-hat. Range finite; default 0.
        error_increment: growth of |epsilon| per step since a classifier (or table entry)
            was last active (section 4; Figure 6's PredErr column steps by 0.0002).
            Range >= 0; default 0.0002.

    """

    RANGES: ClassVar[dict[str, Bounds]] = {
        "gamma": UNIT, "eta": UNIT_NO_ZERO, "payoff": FINITE, "q0": FINITE, "error_increment": NON_NEGATIVE,
    }

    gamma: float = 0.95  # gamma, eq. 2
    eta: float = 0.5  # eta, eq. 1
    payoff: float = 1.0  # r_{t+1} at the goal
    q0: float = 0.0  # initial Q-hat(x, a)
    error_increment: float = 0.0002  # growth of |epsilon| per step (strength, eq. 4)


@dataclass(frozen=True)
class TabularParams(QLearningParams):
    """LT-QL: Q-learning over a look-up table of all states x all actions.

    The exported table entries get strength 1 - |epsilon| with the same error growth as
    CS-QL's classifiers. Every field is :class:`QLearningParams`' or :class:`CommonParams`'.
    """


@dataclass(frozen=True)
class CSQLParams(QLearningParams):
    """CS-QL: Q-learning over Q-classifiers (eq. 1-4).

    Attributes:
        t_decay: CS-QL's own temperature decay. With LT-QL's 0.996 CS-QL first reaches the
            optimal 8 steps at trial 850; with 0.9955 at 700, as in the paper, while LT-QL
            (0.996) stays at the paper's 1150. Measured over 50 cycles x 2500 trials.
            Range (0, 1]; default 0.9955.
        sweep: after the trials, sweep the world model (the add-delete R-classifiers):
            greedy passes over every (start, goal) pair updating with eq. 1-2 (with
            ``sweep_backup_all``, every candidate on the paths: value iteration through the
            model). ``train --sweep value-iteration|none`` sets it. It does not learn from
            experience: with one trial it already makes every pair optimal at n = 4 and 5
            (docs/what_learns.md). False is the paper-faithful variant. A flag; default true.
        sweep_passes: the most passes of the sweep. Range >= 0 (an integer); default 50.
        sweep_tolerance: the sweep stops after a pass whose largest |epsilon| is at most
            this (Q-values then agree with eq. 2 along every greedy path). Range >= 0;
            default 0.001.
        sweep_backup_all: in the sweep, back up every candidate of each node on the greedy
            paths through the world model (Dyna-style planning, Sutton 1990), not only the
            selected one. The greedy sweep alone cannot repair a path whose better action
            was never tried; this one can. A flag; default false (true for n > 3, see
            :func:`defaults_for_blocks`).
        sweep_eta: eta of eq. 1 in those Dyna backups. The world model is deterministic,
            so a full step is exact and the backups converge in a few passes (eta 0.5
            needs about 20 at n = 5). Range (0, 1]; default 1.
        sweep_greedy_tail: greedy-only passes after the sweep's passes: they leave only
            each pair's greedy classifier recently active, so pruning by strength keeps
            exactly one per (state, goal). Range >= 0 (an integer); default 0. It is 3 for n > 3.
        replay_ratio: the cap of experience replay (:mod:`csql_sim.learners.paper.replay`): at most
            this many replay backups per experienced trial step; 0 is no replay.
            ``train --replay R`` sets it. Range [0, 1e+06]; default 0.
        replay_hindsight: replay each experienced (state, action) transition for every goal
            (hindsight relabelling), not only for the goal it was taken for. A flag; default true.
        replay_eta: eta of eq. 1 in replay backups. Range (0, 1]; default 1.
        replay_tolerance: a replay phase stops after a pass whose largest |epsilon| is at
            most this. Range >= 0; default 0. At 0 a phase runs until nothing changes (or the cap).

    """

    RANGES: ClassVar[dict[str, Bounds]] = {
        "sweep_passes": NON_NEGATIVE, "sweep_tolerance": NON_NEGATIVE, "sweep_eta": UNIT_NO_ZERO,
        "sweep_greedy_tail": NON_NEGATIVE, "replay_ratio": RATIO, "replay_eta": UNIT_NO_ZERO,
        "replay_tolerance": NON_NEGATIVE,
    }

    t_decay: float = 0.9955  # T_{k+1} = T_k * decay; reproduces "optimal by ~700 trials"
    sweep: bool = True  # value iteration through the world model after the trials (ours; False = paper)
    sweep_passes: int = 50  # at most this many passes
    sweep_tolerance: float = 0.001  # stop when every |epsilon| of a pass is below
    sweep_backup_all: bool = False  # sweep backs up every candidate (Dyna), not just the greedy one
    sweep_eta: float = 1.0  # eta of the Dyna backups (sweep_backup_all only)
    sweep_greedy_tail: int = 0  # greedy-only passes after the sweep's passes
    replay_ratio: float = 0.0  # cap: replay backups per experienced step (0: no replay)
    replay_hindsight: bool = True  # replay each experienced transition for every goal
    replay_eta: float = 1.0  # eta of the replay backups
    replay_tolerance: float = 0.0  # a replay phase stops when no |epsilon| of a pass exceeds this


@dataclass(frozen=True)
class BucketBrigadeParams(CommonParams):
    """CS-BB-BZ / CS-BB-RW: Holland's bucket brigade, no discounting.

    Each step the active classifier pays a bid ``bid * S`` to the classifier active one
    step before it; at the goal it receives ``bid * payoff`` (the payoff enters through the
    same bucket, as in Wilson's ZCS, so strengths tend to ``payoff`` on every chain that
    reaches the goal). Matched candidates that were not selected pay a tax ``tax * S``.

    The constants were chosen with ``benchmarks/learning_bucket_brigade.py`` against the paper's
    statements about Figure 7 (:mod:`csql_sim.jobs.figure7_statements`; docs/learning.md has
    the sweep). ``bid`` is the speed at which strength flows back along a chain: Figure
    7(b)'s "the bucket-brigade curves rise faster than CS-QL's" needs bid 0.8 (at 0.5 they
    tie with CS-QL, whose eta is 0.5 but whose targets are discounted). ``s0`` sets when
    CS-BB-RW degrades: an untried alternative wins the roulette wheel with odds ``s0 / S``
    and, once chosen, is paid by its strong successor, so it grows about geometrically
    from ``s0``. ``tax`` slows that growth and keeps CS-BB-BZ at the optimum once its
    temperature is low. No setting met every statement: in the sweep CS-BB-RW's mean
    reaches exactly 8 only at s0 = 0.002, and then it ends at 10-20 steps, not ~75.

    Attributes:
        bid: bid coefficient, the fraction of strength bid by the active classifier.
            Range (0, 1]; default 0.8.
        tax: tax rate on matched, not selected candidates. Range [0, 1), and below bid;
            default 0.005. At tax >= bid an alternative can never grow back; at 0.1 and
            above some cycles trap themselves in loops of taxed-out classifiers.
        payoff: payoff at the goal. Range > 0; default 1. At 1 strengths and Q-values
            share Figure 7(b)'s scale. The roulette wheel does not depend on it; Boltzmann
            selection does (through T / payoff).
        s0: initial strength (positive, for the roulette wheel). Range > 0, and at most
            payoff; default 0.015.

    """

    RANGES: ClassVar[dict[str, Bounds]] = {
        "bid": UNIT_NO_ZERO, "tax": Bounds(0.0, 1.0, high_open=True), "payoff": POSITIVE, "s0": POSITIVE,
    }

    bid: float = 0.8  # bid coefficient c_bid
    tax: float = 0.005  # tax on matched, unselected candidates
    payoff: float = 1.0  # payoff at the goal
    s0: float = 0.015  # initial strength

    def __post_init__(self) -> None:
        """Each range, then the two that depend on other fields (tax < bid, s0 <= payoff)."""
        super().__post_init__()
        if self.tax >= self.bid:
            raise ParamsError(f"tax must be below bid ({self.bid:g}), got {self.tax!r}")
        if self.s0 > self.payoff:
            raise ParamsError(f"s0 must be at most payoff ({self.payoff:g}), got {self.s0!r}")


def _shown(value: object) -> str:
    """``repr(value)``, or the number of digits of an integer of more than 20."""
    big = isinstance(value, int) and abs(value) >= 10**20
    return f"an integer of {len(str(abs(value)))} digits" if big else repr(value)


def _describe(bounds: Bounds) -> str:
    text = str(bounds)
    if text == "finite":
        return "a finite number"
    return f"in {text}" if text[0] in "[(" else text


PARAMS_BY_METHOD: dict[str, type[CommonParams]] = {
    "lt-ql": TabularParams,
    "cs-ql": CSQLParams,
    "cs-bb-bz": BucketBrigadeParams,
    "cs-bb-rw": BucketBrigadeParams,
    "xcs-ql": CSQLParams,  # CS-QL's critic with an XCS-style population (learners/generalize/xcs_ql.py)
}


def default_params(method: str) -> CommonParams:
    """The default parameters of a method."""
    try:
        return PARAMS_BY_METHOD[method]()
    except KeyError:
        raise ParamsError(f"unknown method {method!r}; choose from {', '.join(PARAMS_BY_METHOD)}") from None


GREEDY_PASS_STEPS = {2: 40, 3: 2046, 4: 109_208, 5: 7_292_290}
"""Sum of the optimal plan lengths over every ordered pair: the steps of one greedy sweep
pass once every plan is optimal (a test recomputes them; n = 6 is extrapolated)."""
DEFAULT_TRIALS = {2: 2500, 3: 2500, 4: 20_000, 5: 20_000, 6: 50_000}
"""Training trials per n (``csql-sim train`` and ``experiment`` without ``--trials``)."""


def default_trials(n: int) -> int:
    """The number of training trials used when none is given."""
    return DEFAULT_TRIALS.get(n, 2500)


def defaults_for_blocks(method: str, n: int) -> CommonParams:
    """The defaults of ``method`` for n blocks; n <= 3 keeps the paper-tuned defaults unchanged.

    For n > 3:

    * ``t_decay = (t_min / t0) ** (1 / (0.6 * default_trials(n)))``: T reaches its floor
      after 60% of the trials, as 0.9955 does at n = 3;
    * ``step_cap = max(10000, 10 * states)``;
    * ``error_increment = 0.0002 * P3 / Pn``, Pn the steps of one greedy pass over all
      pairs (:data:`GREEDY_PASS_STEPS`): |epsilon| grows as much per sweep pass as at
      n = 3, so pruning at 0.1 still separates each pair's greedy classifier;
    * CS-QL: the Dyna sweep (``sweep_backup_all``) and 3 greedy passes after it.
    """
    base = default_params(method)
    if n <= 3:
        return base
    from csql_sim.core.state.world import all_states

    overrides: dict = {
        "t_decay": (base.t_min / base.t0) ** (1.0 / (0.6 * default_trials(n))),
        "step_cap": max(10_000, 10 * len(all_states(n))),
    }
    if isinstance(base, QLearningParams):
        steps = GREEDY_PASS_STEPS.get(n, 70 * GREEDY_PASS_STEPS[5])
        overrides["error_increment"] = base.error_increment * GREEDY_PASS_STEPS[3] / steps
    if isinstance(base, CSQLParams):
        overrides.update(sweep_backup_all=True, sweep_greedy_tail=3)
    return dataclasses.replace(base, **overrides)


def with_overrides(params: CommonParams, overrides: dict, source: str = "parameters") -> CommonParams:
    """Replace fields of ``params``; an unknown key or a wrong type is a ParamsError."""
    known = {f.name: f for f in fields(params)}
    clean = {}
    for key, value in overrides.items():
        if key not in known:
            raise ParamsError(f"{source}: unknown parameter {key!r} for {type(params).__name__}")
        current = getattr(params, key)
        if isinstance(current, bool):
            ok = isinstance(value, bool)
        elif isinstance(current, int):
            ok = isinstance(value, int) and not isinstance(value, bool)
        else:
            ok = isinstance(value, (int, float)) and not isinstance(value, bool)
            try:
                value = float(value) if ok else value
            except OverflowError:
                raise ParamsError(f"{source}: {key} must be a finite float64, got {_shown(value)}") from None
        if not ok:
            raise ParamsError(f"{source}: {key} must be {type(current).__name__}, got {value!r}")
        clean[key] = value
    try:
        return dataclasses.replace(params, **clean)
    except ParamsError as exc:
        raise ParamsError(f"{source}: {exc}") from None


def load_params(path: str | os.PathLike, method: str, n: int = 3) -> CommonParams:
    """Defaults of ``method`` for n blocks overridden by a YAML mapping.

    The file is either a flat mapping of parameters, or a mapping from method names to
    such mappings (only ``method``'s entry is applied).
    """
    p = os.fspath(path)
    try:
        doc = load_yaml(read_text_file(p, MAX_FILE_BYTES, "parameter file"), p)
    except InputFileError as exc:
        raise ParamsError(str(exc)) from None
    except (ValueError, OverflowError) as exc:  # a value PyYAML cannot build: an integer of 5,000 digits
        raise ParamsError(f"{p}: a YAML value cannot be read ({exc.__class__.__name__})") from None
    if doc is None:
        doc = {}
    if not isinstance(doc, dict):
        raise ParamsError(f"{p}: expected a mapping of parameter names to values")
    if any(k in PARAMS_BY_METHOD for k in doc):
        stray = [k for k in doc if k not in PARAMS_BY_METHOD]
        if stray:
            raise ParamsError(f"{p}: unknown method {stray[0]!r}")
        doc = doc.get(method) or {}
        if not isinstance(doc, dict):
            raise ParamsError(f"{p}: the entry for {method} must be a mapping")
    return with_overrides(defaults_for_blocks(method, n), doc, source=str(p))


def resolve_params(
    method: str, params: CommonParams | dict | str | os.PathLike | None, n: int = 3
) -> CommonParams:
    """Parameters from None (the defaults for n blocks), a dataclass, a dict of overrides or a YAML path."""
    if params is None:
        return defaults_for_blocks(method, n)
    if isinstance(params, CommonParams):
        expected = PARAMS_BY_METHOD.get(method)
        if expected is None:
            default_params(method)
        if type(params) is not expected:
            raise ParamsError(f"{method} needs {expected.__name__}, got {type(params).__name__}")
        return params
    if isinstance(params, dict):
        return with_overrides(defaults_for_blocks(method, n), params)
    return load_params(params, method, n)
