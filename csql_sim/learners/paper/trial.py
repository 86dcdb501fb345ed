"""Step learners and the trial loop that drives them: act, step the model, learn.

The reference engines of the four methods are step learners (:class:`StepLearner`):
besides the :class:`~csql_sim.learners.paper.learner.Learner` contract they are driven one step
at a time, by the trial loop here and by the symbolic and physical environments, through:

* :meth:`StepLearner.begin_episode` before an episode's first action;
* :meth:`StepLearner.act`: the action index to take for an observed state message;
* :meth:`StepLearner.learn`: credit assignment from the :class:`Transition` that followed.

A step learner also offers :attr:`StepLearner.model`, the transition model its training
trials run on: the R-classifiers' world model for the classifier-system learners
(Dyna-style planning, as the paper's trials are), the true transition table for LT-QL.
:meth:`StepLearner.learn` ticks the clock before its update, so a classifier updated at
the last step has grown no error yet (Figure 6's last row).

A trial (:func:`run_trial`) runs one task on the learner's own transition model until the
goal message or the step cap. Training (:func:`run_training`, which is
:meth:`StepLearner.train`) runs random tasks with the test task every :data:`TEST_EVERY`
trials, at the temperature of the schedule (eq. 3).
"""

from __future__ import annotations

from abc import abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from csql_sim.core.state.message import format_state_message
from csql_sim.learners.paper.learner import TEST_EVERY, Curve, Learner, Transition, UniformStream
from csql_sim.learners.paper.params import CommonParams

__all__ = ["TEST_EVERY", "Curve", "StepLearner", "TransitionModel", "TrialResult", "run_trial", "run_training"]


class TransitionModel(Protocol):
    """What training trials step on: the next state message after an action index."""

    def step(self, message: str, action: int) -> str:
        """The state message after ``action`` in ``message``."""
        ...


class StepLearner(Learner):
    """A learner driven one step at a time (the reference engines of the four methods).

    Args:
        n: number of blocks.
        params: the learner's parameter dataclass.
        rng: the only source of randomness (through :attr:`uniforms`).

    """

    def __init__(self, n: int, params: CommonParams, rng: np.random.Generator) -> None:
        super().__init__(n, params)
        self.uniforms = UniformStream(rng)
        self.t = 0
        self._messages: dict[tuple[int, int], str] = {}

    def message(self, state: int, goal: int) -> str:
        """The state message of state index ``state`` for goal index ``goal`` (memoized)."""
        text = self._messages.get((state, goal))
        if text is None:
            text = self._messages[(state, goal)] = format_state_message(self.world.states[state], goal)
        return text

    def train(self, trials: int, on_trial: Callable[[int], None] | None = None,
              test_every: int = TEST_EVERY) -> Curve:
        """:meth:`Learner.train`: :func:`~csql_sim.learners.paper.trial.run_training` on :attr:`model`."""
        return run_training(self, trials, test_every, on_trial)

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


@dataclass(frozen=True)
class TrialResult:
    """One trial.

    Attributes:
        steps: actions taken.
        reached: whether the goal was reached.
        value_mean: mean value (Q-value or strength) of the chosen actions, when tracked.

    """

    steps: int
    reached: bool
    value_mean: float


def run_trial(learner: StepLearner, start: int, goal: int, temperature: float, cap: int | None = None,
              track: bool = False) -> TrialResult:
    """One trial from state ``start`` to state ``goal`` on the learner's model, learning each step.

    Args:
        learner: any step learner (a reference engine).
        start: start state index.
        goal: goal state index (distinct from ``start``).
        temperature: T of eq. 3 for the whole trial (0 = greedy).
        cap: step cap (default ``params.step_cap``).
        track: average the chosen actions' values (for the test task).

    """
    observation = learner.message(start, goal)
    goal_message = learner.message(goal, goal)
    cap = learner.params.step_cap if cap is None else cap
    model = learner.model
    act, learn = learner.act, learner.learn
    learner.begin_episode()
    value_sum = 0.0
    steps = 0
    reached = False
    while steps < cap:
        action = act(observation, temperature)
        if track:
            value_sum += learner.value(observation, action)
        nxt = model.step(observation, action)
        reached = nxt == goal_message
        learn(Transition(observation, action, nxt, reached))
        steps += 1
        if reached:
            break
        observation = nxt
    return TrialResult(steps, reached, value_sum / steps if steps else 0.0)


def run_training(learner: StepLearner, trials: int, test_every: int = TEST_EVERY,
                 on_trial: Callable[[int], None] | None = None) -> Curve:
    """Train for ``trials`` random tasks; run the test task every ``test_every``.

    The test task runs before trial 0 and after every ``test_every`` trials (so also after
    the last one when ``trials`` is a multiple); it learns like any trial, at the
    temperature of the training trial it precedes.
    """
    test_start, test_goal = learner.test_indices()
    count = len(learner.world.states)
    marks, steps, values = [], [], []
    for k in range(trials + 1):
        temperature = learner.params.temperature(k)
        if test_every and k % test_every == 0:
            result = run_trial(learner, test_start, test_goal, temperature, track=True)
            marks.append(k)
            steps.append(result.steps)
            values.append(result.value_mean)
        if k == trials:
            break
        start, goal = learner.uniforms.task(count)
        run_trial(learner, start, goal, temperature)
        if on_trial is not None:
            on_trial(k)
    return Curve(tuple(marks), tuple(steps), tuple(values))
