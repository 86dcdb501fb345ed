"""What every learner is: act on an observation, learn from a transition, export a rule base.

The trial loop (:mod:`csql_sim.learners.trial`), the symbolic Gymnasium environment and
the physical one all drive a learner through this interface and nothing else:

* :meth:`Learner.begin_episode` before an episode's first action;
* :meth:`Learner.act`: the action index to take for an observed state message;
* :meth:`Learner.learn`: credit assignment from the :class:`Transition` that followed;
* :meth:`Learner.rulebase`: the learned classifiers as a rule base.

A learner also offers :attr:`Learner.model`, the transition model its training trials
run on: the R-classifiers' world model for the classifier-system learners (Dyna-style
planning, as the paper's trials are), the true transition table for LT-QL.

Units: the learner's clock :attr:`Learner.t` counts learning steps over its whole life,
test tasks and sweeps included; :meth:`learn` ticks it before its update, so a
classifier updated at the last step has grown no error yet (Figure 6's last row).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import NamedTuple, Protocol

import numpy as np

from csql_sim.core.message import format_state_message
from csql_sim.core.rulebase import RuleBase
from csql_sim.core.world import BlocksWorld
from csql_sim.learners.params import CommonParams

BATCH = 4096


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


class TransitionModel(Protocol):
    """What training trials step on: the next state message after an action index."""

    def step(self, message: str, action: int) -> str:
        """The state message after ``action`` in ``message``."""
        ...


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
    """Base of the four learners.

    Args:
        n: number of blocks.
        params: the learner's parameter dataclass.
        rng: the only source of randomness (through :attr:`uniforms`).

    """

    method = "base"

    def __init__(self, n: int, params: CommonParams, rng: np.random.Generator) -> None:
        self.n = n
        self.params = params
        self.world = BlocksWorld.of(n)
        self.uniforms = UniformStream(rng)
        self.t = 0
        self._messages: dict[tuple[int, int], str] = {}

    def message(self, state: int, goal: int) -> str:
        """The state message of state index ``state`` for goal index ``goal`` (memoized)."""
        text = self._messages.get((state, goal))
        if text is None:
            text = self._messages[(state, goal)] = format_state_message(self.world.states[state], goal)
        return text

    @property
    @abstractmethod
    def model(self) -> TransitionModel:
        """The transition model training trials run on."""

    def begin_episode(self) -> None:  # noqa: B027 - a hook; most learners need nothing here
        """Called before an episode's first action (the bucket brigade forgets its predecessor)."""

    @abstractmethod
    def act(self, observation: str, temperature: float) -> int:
        """Choose an action index for a state message (eq. 3 at ``temperature``; 0 = greedy)."""

    @abstractmethod
    def value(self, observation: str, action: int) -> float:
        """The learner's current value of ``action`` in ``observation`` (Q-value or strength)."""

    @abstractmethod
    def learn(self, transition: Transition) -> None:
        """Credit assignment for the transition that followed the last :meth:`act`."""

    @abstractmethod
    def rulebase(self, meta: dict | None = None) -> RuleBase:
        """The learned classifiers (with R-classifiers, if any), settled to the current step."""
