"""Benchmark: CS-QL training against a plain dict-based tabular Q-learner, same trials.

The plain learner is what one would write without a classifier system: a dict from
(state, goal) to a dict of legal action -> Q, the world's integer transition table, the
same Boltzmann selection, temperature schedule, test-task schedule and uniform stream.
Both learners therefore see the same random tasks; the ratio compares steps per second.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from csql_sim.learners.learner import UniformStream
from csql_sim.learners.params import CSQLParams
from csql_sim.learners.selection import boltzmann
from csql_sim.learners.trial import TEST_EVERY, run_training
from csql_sim.task import test_task
from csql_sim.world import BlocksWorld


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
class BenchResult:
    """Steps and best wall time of each learner over the repeats."""

    trials: int
    csql_steps: int
    csql_seconds: float
    plain_steps: int
    plain_seconds: float

    @property
    def ratio(self) -> float:
        """CS-QL steps/s divided by the plain learner's steps/s (>= 1: CS-QL is faster)."""
        return (self.csql_steps / self.csql_seconds) / (self.plain_steps / self.plain_seconds)


def bench(trials: int = 2500, seed: int = 0, repeats: int = 5) -> BenchResult:
    """Time CS-QL and the plain learner on the same trials; the best of ``repeats`` each."""
    from csql_sim.learners import make_learner

    best_c = best_p = float("inf")
    steps_c = steps_p = 0
    for _ in range(repeats):
        t0 = time.perf_counter()
        learner = make_learner("cs-ql", 3, seed=seed)
        run_training(learner, trials)
        best_c = min(best_c, time.perf_counter() - t0)
        steps_c = learner.t
        t0 = time.perf_counter()
        steps_p = plain_q_learning(trials, seed)
        best_p = min(best_p, time.perf_counter() - t0)
    return BenchResult(trials, steps_c, best_c, steps_p, best_p)
