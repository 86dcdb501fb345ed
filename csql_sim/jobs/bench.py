"""Benchmark: both engines of CS-QL and of LT-QL, and a plain dict-based Q-learner, same trials.

The plain learner is what one would write without a classifier system: a dict from
(state, goal) to a dict of legal action -> Q, the world's integer transition table, the
same Boltzmann selection, temperature schedule, test-task schedule and uniform stream.
Both learners therefore see the same random tasks; the ratio compares steps per second.
LT-QL's reference and array engines also run the same trials (the same trajectory), so
their ratio is one of CPU times on identical work.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from csql_sim.core.model.task import test_task
from csql_sim.core.state.world import BlocksWorld
from csql_sim.learners.paper import TEST_EVERY, CSQLParams, UniformStream, boltzmann


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
    """The learners on the same trials, and whether each method's two engines agree.

    Attributes:
        trials: training trials of every run.
        reference: CS-QL's reference engine.
        fast: CS-QL's array engine.
        plain: the plain dict-based Q-learner.
        identical: the two CS-QL engines wrote the same rule file.
        lt_reference: LT-QL's reference engine.
        lt_fast: LT-QL's array engine.
        lt_identical: the two LT-QL engines wrote the same rule file.

    """

    trials: int
    reference: EngineTiming
    fast: EngineTiming
    plain: EngineTiming
    identical: bool
    lt_reference: EngineTiming
    lt_fast: EngineTiming
    lt_identical: bool

    @property
    def ratio(self) -> float:
        """Reference CS-QL steps/s over the plain learner's (>= 1: the classifier system is faster)."""
        return self.reference.rate / self.plain.rate

    @property
    def fast_ratio(self) -> float:
        """Fast CS-QL steps/s over the plain learner's."""
        return self.fast.rate / self.plain.rate

    @property
    def lt_ratio(self) -> float:
        """LT-QL's array engine steps/s over its reference engine's (the same steps)."""
        return self.lt_fast.rate / self.lt_reference.rate


def _best(name: str, job, repeats: int) -> tuple[EngineTiming, object]:
    best, steps, out = float("inf"), 0, None
    for _ in range(repeats):
        t0 = time.process_time()
        out, steps = job()
        best = min(best, time.process_time() - t0)
    return EngineTiming(name, steps, best), out


def bench(trials: int = 2500, seed: int = 0, repeats: int = 5) -> BenchResult:
    """Time both engines of CS-QL and of LT-QL, and the plain learner, on the same trials (n = 3).

    Times are CPU seconds of this process (``time.process_time``), the best of
    ``repeats``, so other processes on a shared machine disturb them less. The fast
    engines are compiled (or loaded from numba's cache) before timing. A method's
    trajectories are identical when both its engines write the same rule file (npz
    bytes: every field at full precision).
    """
    from csql_sim.learners.training import make_learner

    def run(method: str, engine: str):
        def job():
            learner = make_learner(method, 3, seed=seed, engine=engine)
            learner.train(trials)
            return learner, learner.t
        return job

    def same(a, b) -> bool:
        return a.file_bytes("rules.npz", {}) == b.file_bytes("rules.npz", {})

    run("cs-ql", "fast")()  # compile
    run("lt-ql", "fast")()
    ref, ref_learner = _best("reference", run("cs-ql", "reference"), repeats)
    fast, fast_learner = _best("fast", run("cs-ql", "fast"), repeats)
    plain, _ = _best("plain", lambda: (None, plain_q_learning(trials, seed)), repeats)
    lt_ref, lt_ref_learner = _best("lt-ql reference", run("lt-ql", "reference"), repeats)
    lt_fast, lt_fast_learner = _best("lt-ql fast", run("lt-ql", "fast"), repeats)
    return BenchResult(trials, ref, fast, plain, same(ref_learner, fast_learner), lt_ref, lt_fast,
                       same(lt_ref_learner, lt_fast_learner))
