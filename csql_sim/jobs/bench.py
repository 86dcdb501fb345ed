"""Benchmark: the two CS-QL engines against a plain dict-based tabular Q-learner, same trials.

The plain learner is what one would write without a classifier system: a dict from
(state, goal) to a dict of legal action -> Q, the world's integer transition table, the
same Boltzmann selection, temperature schedule, test-task schedule and uniform stream.
Both learners therefore see the same random tasks; the ratio compares steps per second.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from csql_sim.core.task import test_task
from csql_sim.core.world import BlocksWorld
from csql_sim.learners.learner import UniformStream
from csql_sim.learners.params import CSQLParams
from csql_sim.learners.selection import boltzmann
from csql_sim.learners.trial import TEST_EVERY


def plain_q_learning(trials: int, seed: int, params: CSQLParams | None = None) -> int:
    """Train a plain dict-based tabular Q-learner; returns the steps taken."""
    p = params or CSQLParams()
    world = BlocksWorld.of(3)
    legal, next_state = world.legal, world.next_state
    count = len(world.states)
    task = test_task(3)
    test = (world.state_index(task.start), world.state_index(task.goal))
    uniforms = UniformStream(np.random.default_rng(seed))
    q: dict[tuple[int, int], dict[int, float]] = {}
    steps = 0
    for k in range(trials + 1):
        temperature = p.temperature(k)
        tasks = [test] if k % TEST_EVERY == 0 else []
        if k < trials:
            tasks.append(None)
        for task in tasks:
            s, g = uniforms.task(count) if task is None else task  # random after test, as in training
            for _ in range(p.step_cap):
                row = q.get((s, g))
                if row is None:
                    row = q[(s, g)] = {a: 0.0 for a in legal[s]}
                actions = list(row)
                a = actions[boltzmann(list(row.values()), temperature, uniforms.next())]
                nxt = next_state[s][a]
                if nxt == g:
                    target = p.payoff
                else:
                    following = q.get((nxt, g))
                    target = p.gamma * max(following.values()) if following else 0.0
                row[a] += p.eta * (target - row[a])
                steps += 1
                s = nxt
                if s == g:
                    break
    return steps


@dataclass(frozen=True)
class EngineTiming:
    """One learner's steps and best CPU time over the repeats."""

    name: str
    steps: int
    seconds: float

    @property
    def rate(self) -> float:
        """Steps per CPU second."""
        return self.steps / self.seconds if self.seconds > 0 else float("inf")


@dataclass(frozen=True)
class BenchResult:
    """The three learners on the same trials, and whether the two CS-QL engines agree."""

    trials: int
    reference: EngineTiming
    fast: EngineTiming
    plain: EngineTiming
    identical: bool

    @property
    def ratio(self) -> float:
        """Reference CS-QL steps/s over the plain learner's (>= 1: the classifier system is faster)."""
        return self.reference.rate / self.plain.rate

    @property
    def fast_ratio(self) -> float:
        """Fast CS-QL steps/s over the plain learner's."""
        return self.fast.rate / self.plain.rate


def _best(name: str, job, repeats: int) -> tuple[EngineTiming, object]:
    best, steps, out = float("inf"), 0, None
    for _ in range(repeats):
        t0 = time.process_time()
        out, steps = job()
        best = min(best, time.process_time() - t0)
    return EngineTiming(name, steps, best), out


def bench(trials: int = 2500, seed: int = 0, repeats: int = 5) -> BenchResult:
    """Time the reference and the fast CS-QL engine and the plain learner on the same trials.

    Times are CPU seconds of this process (``time.process_time``), the best of
    ``repeats``, so other processes on a shared machine disturb them less. The fast
    engine is compiled (or loaded from numba's cache) before timing. The trajectories
    are identical when both engines write the same rule file.
    """
    from csql_sim.core.rulebase import dumps
    from csql_sim.learners.training import make_learner

    def run(engine: str):
        def job():
            learner = make_learner("cs-ql", 3, seed=seed, engine=engine)
            learner.train(trials)
            return learner, learner.t
        return job

    run("fast")()  # compile
    ref, ref_learner = _best("reference", run("reference"), repeats)
    fast, fast_learner = _best("fast", run("fast"), repeats)
    plain, _ = _best("plain", lambda: (None, plain_q_learning(trials, seed)), repeats)
    identical = dumps(ref_learner.rulebase()) == dumps(fast_learner.rulebase())
    return BenchResult(trials, ref, fast, plain, identical)
