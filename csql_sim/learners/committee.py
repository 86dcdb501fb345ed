"""A committee: K populations of lifted Q-classifiers over generated features, learned apart from one seed.

:func:`train_committee` runs LQ-CS (:func:`~csql_sim.learners.lifted_ql.train_lifted`) K times from
an empty population. Member 1 trains on the run's generator itself, so a committee of one is the
single run of the same seed, classifier for classifier; member k > 1 on the (k - 1)-th of
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
from csql_sim.learners.lifted_ql import LiftedParams, LiftedRun, train_lifted
from csql_sim.learners.params import ParamsError


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
                    progress: Callable[[int, int], None] | None = None) -> CommitteeRun:
    """Learn ``size`` populations of lifted Q-classifiers over generated features (module docstring).

    Args:
        params: every member's parameters (``features`` must be ``generated``).
        rng: the run's one generator: member 1's, and the parent of the others'.
        size: members K. Range 1..:data:`~csql_sim.core.policies.committee_policy.MAX_MEMBERS`.
        progress: called with (trials done, trials) over all members, after every sweep.
    """
    if params.features != "generated":
        raise ParamsError("a committee needs generated features (--features generated)")
    if not (isinstance(size, int) and 1 <= size <= MAX_MEMBERS):
        raise ParamsError(f"committee size {size!r} is out of range 1..{MAX_MEMBERS}")
    generators = [rng, *rng.spawn(size - 1)]
    runs = []
    for k, generator in enumerate(generators):
        step = None if progress is None else _offset(progress, k * params.trials, size * params.trials)
        runs.append(train_lifted(params, generator, progress=step))
    return CommitteeRun(tuple(runs))


def _offset(progress: Callable[[int, int], None], before: int, total: int) -> Callable[[int, int], None]:
    """``progress`` called with a member's trials counted after the ``before`` of earlier members."""
    return lambda done, _trials: progress(before + done, total)


__all__ = ["CommitteeRun", "train_committee"]
