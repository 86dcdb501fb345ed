"""The trial loop every learner shares, and the training schedule around it.

A trial runs one task on the learner's own transition model: act, step the model, learn,
until the goal message or the step cap. Training (:func:`run_training`) runs random
tasks with the test task every :data:`TEST_EVERY` trials, at the temperature of the
schedule (eq. 3).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from csql_sim.core.task import test_task
from csql_sim.learners.learner import Learner, Transition

TEST_EVERY = 50


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


def run_trial(learner: Learner, start: int, goal: int, temperature: float, cap: int | None = None,
              track: bool = False) -> TrialResult:
    """One trial from state ``start`` to state ``goal`` on the learner's model, learning each step.

    Args:
        learner: any learner.
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


def run_training(learner: Learner, trials: int, test_every: int = TEST_EVERY,
                 on_trial: Callable[[int], None] | None = None) -> Curve:
    """Train for ``trials`` random tasks; run the test task every ``test_every``.

    The test task runs before trial 0 and after every ``test_every`` trials (so also after
    the last one when ``trials`` is a multiple); it learns like any trial, at the
    temperature of the training trial it precedes.
    """
    task = test_task(learner.n)
    test_start, test_goal = learner.world.state_index(task.start), learner.world.state_index(task.goal)
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
