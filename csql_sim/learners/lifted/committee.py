"""A committee: K populations of lifted Q-classifiers over generated features, learned apart from one seed.

:func:`train_committee` runs LQ-CS over generated features
(:func:`~csql_sim.learners.lifted.generated.train_generated`) K times from an empty population.
Member 1 trains on the run's generator itself, so a committee of one is the single run of the
same seed, classifier for classifier; member k > 1 on the (k - 1)-th of
``rng.spawn(K - 1)``, taken before member 1 trains (spawning leaves the parent's stream as it is).
Each member samples its own training worlds and generates and prunes its own features on them.
The members' plans are combined only when planning
(:class:`~csql_sim.core.policies.committee_policy.CommitteePolicy`: least mean advantage).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from csql_sim.core.policies.committee_policy import MAX_MEMBERS, CommitteePolicy
from csql_sim.core.policies.feature_policy import FeaturePolicy
from csql_sim.infra.backends import Backend, TaskFailure, map_tasks
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.workers import worker_count
from csql_sim.learners.lifted.generated import train_generated
from csql_sim.learners.lifted.learner import LiftedRun
from csql_sim.learners.lifted.params import LiftedParams
from csql_sim.learners.paper.params import ParamsError


@dataclass(frozen=True)
class CommitteeRun:
    """The members' runs, in order (member 1 first)."""

    members: tuple[LiftedRun, ...]

    @property
    def seconds(self) -> float:
        """Training seconds over all members."""
        return sum(m.seconds for m in self.members)

    def policy(self, meta: dict | None = None) -> CommitteePolicy:
        """The committee's greedy policy."""
        policies = [m.policy(meta) for m in self.members]
        if not all(isinstance(p, FeaturePolicy) for p in policies):
            raise ParamsError("a committee needs generated features")
        return CommitteePolicy(policies, meta)


def train_committee(params: LiftedParams, rng: np.random.Generator, size: int,
                    progress: Callable[[int, int], None] | None = None, workers: int | None = 1) -> CommitteeRun:
    """Learn ``size`` populations of lifted Q-classifiers over generated features (module docstring).

    Args:
        params: every member's parameters (``features`` must be ``generated``).
        rng: the run's one generator: member 1's, and the parent of the others'.
        size: members K. Range 1..:data:`~csql_sim.core.policies.committee_policy.MAX_MEMBERS`.
        progress: called with (trials done, trials) over all members: after every sweep in this
            process, or as each member finishes when they train in worker processes.
        workers: processes that train members at once (1, the default: in this process, one after
            another; None: every core); at most the cores and ``size``. The members are the same
            whatever the number.
    """
    if params.features != "generated":
        raise ParamsError("a committee needs generated features (--features generated)")
    if not (isinstance(size, int) and 1 <= size <= MAX_MEMBERS):
        raise ParamsError(f"committee size {size!r} is out of range 1..{MAX_MEMBERS}")
    if workers is not None and not (isinstance(workers, int) and workers >= 1):
        raise ParamsError(f"workers {workers!r} must be a positive integer")
    generators = [rng, *rng.spawn(size - 1)]
    if worker_count(workers, size) > 1:
        return CommitteeRun(_train_apart(params, generators, workers, progress))
    runs = []
    for k, generator in enumerate(generators):
        step = None if progress is None else _offset(progress, k * params.trials, size * params.trials)
        runs.append(train_generated(params, generator, progress=step))
    return CommitteeRun(tuple(runs))


def _train_apart(params: LiftedParams, generators: list[np.random.Generator], workers: int | None,
                 progress: Callable[[int, int], None] | None) -> tuple[LiftedRun, ...]:
    """Each member trained in a worker process (:func:`~csql_sim.infra.backends.map_tasks`)."""
    done = [0]

    def finished(_k: int, run: LiftedRun | TaskFailure) -> LiftedRun | TaskFailure:
        done[0] += 1
        if progress is not None:
            progress(done[0] * params.trials, len(generators) * params.trials)
        return run

    runs = map_tasks(_train_member, [(params, g) for g in generators], Backend(workers=workers), on_result=finished)
    for k, run in enumerate(runs, 1):
        if isinstance(run, TaskFailure):
            raise CsqlError(f"committee member {k} failed: {run.reason}")
    return tuple(runs)


def _train_member(job: tuple[LiftedParams, np.random.Generator]) -> LiftedRun:
    """One member's training (in a worker)."""
    params, generator = job
    return train_generated(params, generator)


def _offset(progress: Callable[[int, int], None], before: int, total: int) -> Callable[[int, int], None]:
    """``progress`` called with a member's trials counted after the ``before`` of earlier members."""
    return lambda done, _trials: progress(before + done, total)


__all__ = ["CommitteeRun", "train_committee"]
