"""The one learner contract, and the vocabulary the learners share.

Every learner, whichever method and whichever engine runs it (the reference engines on
classifier objects, the array engines of :mod:`~csql_sim.learners.engines.fast_engine` (CS-QL) and
:mod:`~csql_sim.learners.engines.lt_fast` (LT-QL)), is a
:class:`Learner`; callers outside this package use nothing else:

* :meth:`Learner.train`: the training schedule (random tasks, the test task every
  :data:`TEST_EVERY`), with a per-trial callback for progress; returns the test-task
  :class:`Curve`;
* :meth:`Learner.sweep`: the planning sweep that ends training, where the method has one;
* :meth:`Learner.greedy_table`: the greedy policy over the learner's own classifiers;
* :meth:`Learner.rulebase`, :meth:`Learner.file_bytes`, :meth:`Learner.write`: the
  learned classifiers as a rule base, as a rule file's content, written to a file.

The reference engines are also driven one step at a time (act on an observation, learn
from the :class:`Transition` that followed) by the trial loop and the environments:
:class:`~csql_sim.learners.paper.trial.StepLearner`.

Units: the learner's clock :attr:`Learner.t` counts learning steps over its whole life,
test tasks and sweeps included.
"""

from __future__ import annotations

import os
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from csql_sim.core.files.rulebase import RuleBase, file_bytes
from csql_sim.core.model.task import test_task
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.core.state.world import BlocksWorld
from csql_sim.infra.files import write_atomic
from csql_sim.learners.paper.params import CommonParams

BATCH = 4096
TEST_EVERY = 50


class Transition(NamedTuple):
    """One step an agent experienced.

    Attributes:
        observation: the state message the action was chosen in.
        action: the action's index in the stable action order.
        next_observation: the state message observed afterwards.
        terminated: whether the goal was reached.

    """

    observation: str
    action: int
    next_observation: str
    terminated: bool


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


class UniformStream:
    """Uniforms in [0, 1) from one generator, drawn in batches of :data:`BATCH`.

    The stream's order is part of the results: the same seed gives the same uniforms to
    the same draws, whichever learner or engine consumes them.
    """

    def __init__(self, rng: np.random.Generator) -> None:
        self.rng = rng
        self._buf: list[float] = []
        self._pos = 0

    def next(self) -> float:
        """The next uniform."""
        if self._pos >= len(self._buf):
            self._buf, self._pos = self.rng.random(BATCH).tolist(), 0
        u = self._buf[self._pos]
        self._pos += 1
        return u

    def pair(self) -> tuple[float, float]:
        """The next two uniforms (a batch boundary keeps the leftover first)."""
        if self._pos + 2 > len(self._buf):
            self._buf, self._pos = self._buf[self._pos :] + self.rng.random(BATCH).tolist(), 0
        u, v = self._buf[self._pos], self._buf[self._pos + 1]
        self._pos += 2
        return u, v

    def task(self, count: int) -> tuple[int, int]:
        """A random (start, goal) pair of distinct indices below ``count``."""
        u, v = self.pair()
        start = min(int(u * count), count - 1)
        goal = min(int(v * (count - 1)), count - 2)
        return start, goal + (goal >= start)


class Learner(ABC):
    """What every learner is, whichever engine runs it.

    Args:
        n: number of blocks.
        params: the learner's parameter dataclass.

    Attributes:
        method: the method's name (``lt-ql``, ``cs-ql``, ``cs-bb-bz``, ``cs-bb-rw``, ...).
        engine: the engine's name, for messages (both engines write the same files).
        n: number of blocks.
        params: the learner's parameters.
        world: the n-block world (state and action indices).
        t: the clock, learning steps over the learner's life.

    """

    method = "base"
    engine = "reference"
    t: int

    def __init__(self, n: int, params: CommonParams) -> None:
        self.n = n
        self.params = params
        self.world = BlocksWorld.of(n)

    def test_indices(self) -> tuple[int, int]:
        """The test task's (start, goal) state indices (:func:`csql_sim.core.model.task.test_task`)."""
        task = test_task(self.n)
        return self.world.state_index(task.start), self.world.state_index(task.goal)

    # -- training ------------------------------------------------------------------------
    @abstractmethod
    def train(self, trials: int, on_trial: Callable[[int], None] | None = None,
              test_every: int = TEST_EVERY) -> Curve:
        """Train on ``trials`` random tasks, running the test task every ``test_every``.

        The test task runs before trial 0 and after every ``test_every`` trials (so also
        after the last one when ``trials`` is a multiple); it learns like any trial, at the
        temperature of the training trial it precedes.

        Args:
            trials: random training tasks.
            on_trial: called with each training trial's index once it is done (progress).
            test_every: trials between test tasks (0: none).

        Returns:
            The test task's steps and mean value at each test.
        """

    @property
    def max_sweep_passes(self) -> int:
        """The most passes :meth:`sweep` makes (0: it does nothing), for a progress bar."""
        return 0

    def sweep(self, on_pass: Callable[[], None] | None = None) -> int:
        """The planning sweep that ends training, where the method has one; its steps (0: none).

        CS-QL with ``sweep`` on plans over every (start, goal) pair and then runs the test
        task once greedily, so that training ends on the test task as Figure 6 was taken.

        Args:
            on_pass: called after each pass (progress).
        """
        return 0

    # -- what was learned ----------------------------------------------------------------
    @abstractmethod
    def rulebase(self, meta: dict | None = None) -> RuleBase:
        """The learned classifiers (with R-classifiers, if any), settled to the current step."""

    def greedy_table(self) -> GreedyTable:
        """The greedy policy over the learner's classifiers: the best action per (state, goal)."""
        return GreedyTable.from_rulebase(self.rulebase())

    def counts(self) -> tuple[int, int]:
        """The numbers of R- and Q-classifiers in :meth:`rulebase`."""
        kinds = [c.kind for c in self.rulebase().classifiers]
        return kinds.count("R"), len(kinds) - kinds.count("R")

    def file_bytes(self, path: str | os.PathLike, meta: dict) -> str | bytes:
        """The rule file's content for ``path``: npz bytes or YAML text, by suffix."""
        return file_bytes(path, self.rulebase(meta))

    def write(self, path: str | os.PathLike, meta: dict) -> Path:
        """Write the rule file atomically (npz or YAML by suffix); the path written."""
        return write_atomic(path, self.file_bytes(path, meta))
