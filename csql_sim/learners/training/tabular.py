"""Making and training the paper's four learners: the functions the jobs and the CLI call.

* ``lt-ql``: :class:`TabularQ`, Q-learning over a look-up table of all actions, or its
  array engine :class:`~csql_sim.learners.engines.lt_fast.FastTabularQ` (the same trajectory);
* ``cs-ql``: :class:`CSQL`, Q-learning through the classifier system, or its array
  engine :class:`FastCSQL` (the same trajectory);
* ``cs-bb-bz`` / ``cs-bb-rw``: :class:`BucketBrigade` / :class:`BucketBrigadeRoulette`.

:func:`make_learner` is the one place an engine is chosen; every learner it returns is a
:class:`~csql_sim.learners.paper.learner.Learner` and is used through that contract only.
"""

from __future__ import annotations

import os

import numpy as np

from csql_sim.core.classifiers.r_classifier import RClassifier
from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.state.world import BlocksWorld, check_n
from csql_sim.infra.provenance import provenance
from csql_sim.learners.engines.fast_engine import MAX_FAST_BLOCKS, FastCSQL
from csql_sim.learners.generalize.xcs_ql import XCSQL
from csql_sim.learners.paper.bucket_brigade import BucketBrigade, BucketBrigadeRoulette
from csql_sim.learners.paper.cs_ql import CSQL, ClassifierSystemLearner
from csql_sim.learners.paper.learner import Learner
from csql_sim.learners.paper.lt_ql import TabularQ
from csql_sim.learners.paper.params import (
    CommonParams,
    ParamsError,
    default_trials,
    resolve_params,
)
from csql_sim.learners.paper.trial import StepLearner

LEARNERS: dict[str, type[StepLearner]] = {
    "lt-ql": TabularQ,
    "cs-ql": CSQL,
    "cs-bb-bz": BucketBrigade,
    "cs-bb-rw": BucketBrigadeRoulette,
    "xcs-ql": XCSQL,
}
METHODS = tuple(LEARNERS)
PAPER_METHODS = ("lt-ql", "cs-ql", "cs-bb-bz", "cs-bb-rw")
"""The paper's four learners: Figure 7's default methods."""
ENGINES = ("fast", "reference")


def make_learner(
    method: str,
    n: int = 3,
    params: CommonParams | dict | str | os.PathLike | None = None,
    rng: np.random.Generator | None = None,
    seed: int = 0,
    rules: tuple[RClassifier, ...] | None = None,
    engine: str | None = "reference",
) -> Learner:
    """A fresh learner of ``method``; ``rng`` defaults to ``default_rng(seed)``.

    ``rules`` replaces the built-in R-classifiers of the classifier-system learners
    (LT-QL has none and refuses them). ``engine`` picks the implementation of CS-QL and
    LT-QL (see :func:`train`): each has an array engine (:class:`FastCSQL`,
    :class:`FastTabularQ`) with the same trajectory as its reference engine; the
    bucket-brigade methods have the reference engine only.
    """
    if method not in LEARNERS:
        raise ParamsError(f"unknown method {method!r}; choose from {', '.join(METHODS)}")
    if engine not in (None, *ENGINES):
        raise ParamsError(f"unknown engine {engine!r}; choose from {', '.join(ENGINES)}")
    check_n(n)
    resolved = resolve_params(method, params, n)
    generator = rng if rng is not None else np.random.default_rng(seed)
    from csql_sim.learners.engines.lt_fast import MAX_LT_FAST_BLOCKS, FastTabularQ

    replaying = getattr(resolved, "replay_ratio", 0) > 0
    if replaying and engine == "fast":
        raise ParamsError("the fast engine does not replay experience: use --engine reference with --replay")
    fast_ok = not replaying and rules is None and (method == "cs-ql" and n <= MAX_FAST_BLOCKS
                                 or method == "lt-ql" and n <= MAX_LT_FAST_BLOCKS)
    if engine == "fast" and not fast_ok:
        raise ParamsError(f"the fast engine runs cs-ql with the built-in rules up to {MAX_FAST_BLOCKS} blocks "
                          f"and lt-ql up to {MAX_LT_FAST_BLOCKS}")
    if fast_ok and engine in (None, "fast"):
        return FastCSQL(n, resolved, generator) if method == "cs-ql" else FastTabularQ(n, resolved, generator)
    cls = LEARNERS[method]
    if rules is None:
        return cls(n, resolved, generator)
    if not issubclass(cls, ClassifierSystemLearner):
        raise ParamsError(f"{method} has no domain knowledge; R-classifiers apply to the classifier-system methods")
    _check_domain(rules, n)
    return cls(n, resolved, generator, rules)


def _check_domain(rules: tuple[RClassifier, ...], n: int) -> None:
    """Refuse R-classifiers under which some state has no legal action (a trial could not go on)."""
    table = WorldModel(rules, n).table  # raises WorldModelError for predictions that are no state
    stuck = [s for s, legal in enumerate(table.legal) if not legal]
    if stuck:
        state = BlocksWorld.of(n).states[stuck[0]]
        raise ParamsError(f"the R-classifiers give no legal action in {len(stuck)} states, e.g. {state.notation()}: "
                          "they need a precondition and an add-delete rule for the actions there")


def train_learner(
    method: str = "cs-ql",
    trials: int | None = None,
    seed: int = 0,
    n: int = 3,
    params: CommonParams | dict | str | os.PathLike | None = None,
    progress: bool = False,
    engine: str | None = None,
    domain: tuple[RClassifier, ...] | None = None,
) -> tuple[Learner, dict]:
    """Train one agent as :func:`train` does; the learner and the rule file's ``meta``."""
    if trials is None:
        trials = default_trials(n)
    if isinstance(trials, bool) or not isinstance(trials, int) or trials < 0:
        raise ParamsError(f"trials must be a non-negative integer, got {trials!r}")
    learner = make_learner(method, n, params, seed=seed, rules=domain, engine=engine)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=trials, desc=method, unit="trial", leave=False)
    learner.train(trials, on_trial=(lambda _k: bar.update()) if bar is not None else None)
    if bar is not None:
        bar.close()
    phases = {"trials": {"trials": trials, "steps": learner.t, **phase_counts(learner)}}
    replay = getattr(learner, "replay", None)
    if replay is not None and learner.params.replay_ratio > 0:
        backups = replay()
        phases["replay"] = {"backups": backups, **phase_counts(learner)}
    backups = getattr(learner, "backups", 0)
    swept = _sweep(learner, progress)  # CS-QL's planning sweep (with sweep on), ending on the test task
    if learner.max_sweep_passes:
        phases["sweep"] = {"sweep": SWEEP_NAME, "steps": swept, "backups": getattr(learner, "backups", 0) - backups,
                           **phase_counts(learner)}
    # the engine is left out: both engines give the same trajectory and the same file
    meta = {"method": method, "trials": trials, "seed": seed, "steps": learner.t, "sweep_steps": swept,
            "phases": phases, "provenance": provenance(method=method, trials=trials, seed=seed, blocks=n,
                                                       learner_params=learner.params)}
    return learner, meta


SWEEP_NAME = "value-iteration"
"""``train --sweep``'s name of CS-QL's sweep: value iteration through the world model (docs/what_learns.md)."""
SWEEPS = ("none", SWEEP_NAME)


def phase_counts(learner: Learner) -> dict:
    """What the learner plans now: ``optimal_pairs`` (whole greedy paths optimal), ``optimal_steps``, ``pairs``.

    For CS-QL and XCS-QL the critic's Q-classifiers decide (read without settling them);
    the distinct (state, action) pairs trials experienced and the replay backups where the
    learner records them.
    """
    from csql_sim.core.model.optimal_pairs import count_optimal_pairs, count_optimal_steps

    q_greedy = getattr(learner, "q_greedy", None)
    best = q_greedy() if q_greedy is not None else learner.greedy_table().best
    count = len(learner.world.states)
    out = {"optimal_pairs": count_optimal_pairs(best, learner.n), "optimal_steps": count_optimal_steps(best, learner.n),
           "pairs": count * (count - 1)}
    report = getattr(learner, "experience_report", None)
    return {**out, **(report() if report is not None else {})}


def train(
    method: str = "cs-ql",
    trials: int | None = None,
    seed: int = 0,
    n: int = 3,
    params: CommonParams | dict | str | os.PathLike | None = None,
    progress: bool = False,
    engine: str | None = None,
    domain: tuple[RClassifier, ...] | None = None,
) -> RuleBase:
    """Train one agent and return its whole classifier list (R and Q).

    Runs ``trials`` random tasks with the test task every 50
    (:meth:`~csql_sim.learners.paper.learner.Learner.train`), then the learner's
    :meth:`~csql_sim.learners.paper.learner.Learner.sweep`: for CS-QL with ``sweep`` on, the
    final planning sweep and one greedy test task.

    Args:
        method: one of :data:`METHODS`.
        trials: number of random training trials (None: :func:`default_trials` of n).
        seed: seed of the one ``numpy.random.Generator``.
        n: number of blocks.
        params: parameters (dataclass, dict of overrides, YAML path, or None: the defaults
            for n, :func:`~csql_sim.learners.paper.params.defaults_for_blocks`).
        progress: show a tqdm bar on stderr.
        engine: ``"fast"`` (the array engines of CS-QL and LT-QL: same trajectory, same
            file), ``"reference"`` (classifier / row objects), or None: fast where it
            applies (CS-QL with the built-in rules, n <= 6; LT-QL, n <= 5), the reference
            otherwise. Sharded training (6 blocks) is :mod:`csql_sim.learners.training.shards`.
        domain: R-classifiers to use instead of the built-in ones (classifier-system
            methods, reference engine), e.g. rules from ``csql-sim discover``.

    """
    learner, meta = train_learner(method, trials, seed, n, params, progress, engine, domain)
    return learner.rulebase(meta)


def _sweep(learner: Learner, progress: bool) -> int:
    """The learner's sweep, with a bar over its passes when ``progress`` (and it lasts over a second)."""
    if not progress or not learner.max_sweep_passes:
        return learner.sweep()
    from tqdm import tqdm

    with tqdm(total=learner.max_sweep_passes, desc="sweep (passes, at most)", unit="pass",
              leave=False, delay=1.0) as bar:
        return learner.sweep(on_pass=bar.update)
