"""The trial loop every learner shares, and the uniform stream that drives it.

A learner supplies four steps over opaque *nodes* (one per (state, goal) pair it has
seen): :meth:`Learner.node` (sense and process a state), :meth:`Learner.select`,
:meth:`Learner.successor` (the next node, ``None`` at the goal) and
:meth:`Learner.update`. :meth:`Learner.run_trial` strings them together; the test-task
schedule and the random tasks live in :meth:`Learner.run`.

Units: the learner's clock :attr:`Learner.t` counts steps (actions taken) over its whole
life, test tasks and sweeps included; it ticks before a step's update, so a classifier
updated at the last step has grown no error yet (Figure 6's last row, PredErr 0). Error
growth and age are measured on it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from csql_sim.learners.params import CommonParams
from csql_sim.world import TEST_GOAL, TEST_START, BlocksWorld, parse_config

BATCH = 4096
TEST_EVERY = 50
UNSEEN = object()
"""Marks a successor a node has not computed yet (``node.next[i]``)."""


class TrialResult(NamedTuple):
    """One trial: steps taken, whether the goal was reached, mean value per step."""

    steps: int
    reached: bool
    value_mean: float


@dataclass(frozen=True)
class Curve:
    """Test-task measurements over training (one point every ``TEST_EVERY`` trials).

    Attributes:
        trials: the training trial index before which each test ran (0, 50, ..., trials).
        steps: test-task steps at each point.
        values: the test task's mean Q-value (or strength) per step at each point.

    """

    trials: tuple[int, ...]
    steps: tuple[int, ...]
    values: tuple[float, ...]


class Learner:
    """Base of the four learners: the shared trial loop.

    Args:
        n: number of blocks.
        params: the learner's parameter dataclass.
        rng: the only source of randomness; uniforms are drawn from it in batches.

    """

    method = "base"

    def __init__(self, n: int, params: CommonParams, rng: np.random.Generator) -> None:
        self.n = n
        self.params = params
        self.rng = rng
        self.world = BlocksWorld.of(n)
        self.t = 0
        self._buf: list[float] = []
        self._pos = 0
        self._has_begin = type(self).begin_trial is not Learner.begin_trial

    # -- randomness ----------------------------------------------------------------
    def uniform(self) -> float:
        """The next uniform in [0, 1) from the batched stream."""
        if self._pos >= len(self._buf):
            self._buf = self.rng.random(BATCH).tolist()
            self._pos = 0
        u = self._buf[self._pos]
        self._pos += 1
        return u

    def random_task(self) -> tuple[int, int]:
        """A random (start, goal) pair of distinct state indices."""
        count = len(self.world.states)
        if self._pos + 2 > len(self._buf):
            self._buf = self._buf[self._pos :] + self.rng.random(BATCH).tolist()
            self._pos = 0
        u, v = self._buf[self._pos], self._buf[self._pos + 1]
        self._pos += 2
        start = min(int(u * count), count - 1)
        goal = min(int(v * (count - 1)), count - 2)
        return start, goal + (goal >= start)

    # -- the four steps, supplied by each learner ------------------------------------
    def begin_trial(self) -> None:
        """Called before a trial's first step (bucket brigade: forget the predecessor)."""

    def node(self, state: int, goal: int):
        """Sense and process ``state`` for ``goal``: the node holding its candidates."""
        raise NotImplementedError

    def observe(self, message: str):
        """The node of an observed state message (for acting on an environment)."""
        raise NotImplementedError

    def action_index(self, node, i: int) -> int:
        """The world's action index of candidate ``i`` of ``node``."""
        raise NotImplementedError

    def value(self, node, i: int) -> float:
        """Candidate ``i``'s value (Q-value or strength), averaged in the test task."""
        raise NotImplementedError

    def select(self, node, temperature: float, u: float) -> int:
        """Choose a candidate index from the node."""
        raise NotImplementedError

    def successor(self, node, i: int):
        """Compute, store in ``node.next[i]`` and return the node after candidate ``i``.

        ``None`` when it reaches the goal.
        """
        raise NotImplementedError

    def update(self, node, i: int, nxt, t: int) -> None:
        """Credit assignment for candidate ``i`` of ``node`` (next node ``nxt``) at step ``t``."""
        raise NotImplementedError

    # -- the shared loop ---------------------------------------------------------------
    def run_trial(
        self, start: int, goal: int, temperature: float, cap: int | None = None, track: bool = True
    ) -> TrialResult:
        """One trial from ``start`` to ``goal``, learning at every step.

        Nodes keep their successors in ``node.next`` (:data:`UNSEEN` until first
        predicted), so the loop follows a known successor without a call.

        Args:
            start: start state index.
            goal: goal state index (distinct from ``start``).
            temperature: T of eq. 3 for the whole trial (0 = greedy).
            cap: step cap (default ``params.step_cap``).
            track: accumulate the chosen candidates' values (for the test task).

        """
        if cap is None:
            cap = self.params.step_cap
        if self._has_begin:
            self.begin_trial()
        node = self.node(start, goal)
        select, value, successor, update = self.select, self.value, self.successor, self.update
        buf, pos = self._buf, self._pos
        value_sum = 0.0
        t0 = t = self.t
        end = t0 + cap
        reached = False
        while t < end:
            if pos >= len(buf):
                buf, pos = self.rng.random(BATCH).tolist(), 0
            i = select(node, temperature, buf[pos])
            pos += 1
            if track:
                value_sum += value(node, i)
            nxt = node.next[i]
            if nxt is UNSEEN:
                self.t = t
                nxt = successor(node, i)
            t += 1
            update(node, i, nxt, t)
            if nxt is None:
                reached = True
                break
            node = nxt
        self._buf, self._pos, self.t = buf, pos, t
        steps = t - t0
        return TrialResult(steps, reached, value_sum / steps if steps else 0.0)

    def test_task(self) -> tuple[int, int]:
        """The test task's (start, goal) indices for this world (n=3: CBA to BAC)."""
        if self.n != 3:
            states = self.world.states
            return len(states) - 1, 0
        return (
            self.world.state_index(parse_config(TEST_START, 3)),
            self.world.state_index(parse_config(TEST_GOAL, 3)),
        )

    def run(
        self,
        trials: int,
        test_every: int = TEST_EVERY,
        on_trial: Callable[[int], None] | None = None,
    ) -> Curve:
        """Train for ``trials`` random tasks; run the test task every ``test_every``.

        The test task runs before trial 0 and after every ``test_every`` trials (so also
        after the last one when ``trials`` is a multiple); it learns like any trial, at the
        temperature of the training trial it precedes.
        """
        test_start, test_goal = self.test_task()
        marks, steps, values = [], [], []
        for k in range(trials + 1):
            temperature = self.params.temperature(k)
            if test_every and k % test_every == 0:
                result = self.run_trial(test_start, test_goal, temperature)
                marks.append(k)
                steps.append(result.steps)
                values.append(result.value_mean)
            if k == trials:
                break
            start, goal = self.random_task()
            self.run_trial(start, goal, temperature, track=False)
            if on_trial is not None:
                on_trial(k)
        return Curve(tuple(marks), tuple(steps), tuple(values))
