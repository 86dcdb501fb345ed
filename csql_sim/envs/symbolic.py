"""The symbolic blocks world as a Gymnasium environment.

* Observation: the state message (``S0111000ttt0000C``; the goal code is its last field);
  past six blocks (7..26) the large message form, with the goal written out
  (:mod:`csql_sim.envs.relational`).
* Actions: ``Discrete(len(all_actions(n)))``; action ``i`` has the paper's code ``i + 1``.
  ``info["action_mask"]`` (int8, 1 = legal) lists the legal ones. An illegal action
  leaves the state unchanged (as LT-QL assumes) and sets ``info["illegal"]``.
* Reward: 1 on reaching the goal (``terminated``), 0 otherwise; ``truncated`` after
  ``max_steps``.
* ``reset(seed=..., options={"start": ..., "goal": ...})``: start and goal as a
  :class:`State`, a configuration (``"CBA"``), or a state index (past six: a
  State, a configuration or a rank); either missing is drawn from the environment's
  generator (distinct from the other). Or ``options={"problem": "p.pddl"}``: a PDDL
  problem's start, goal (possibly partial) and object names (:mod:`csql_sim.envs.problem`).

:func:`run_env_episode` lets a learner act on such an environment (the physical world
offers the same interface) through its step-level act/learn interface
(:class:`~csql_sim.learners.paper.trial.StepLearner`), learning from the *observed* next state.
"""

from __future__ import annotations

import os
from typing import Any, NamedTuple

import gymnasium as gym
import numpy as np

from csql_sim.core.classifiers.r_classifier import AddDeleteRule, PreconditionRule
from csql_sim.core.files.rulebase import load
from csql_sim.core.model.transition_table import true_table
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.state.message import DIGITS, format_state_message, layout
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.relational_message import format_large_message, message_length
from csql_sim.core.state.state import default_names
from csql_sim.core.state.world import (
    MAX_BLOCKS,
    Action,
    BlocksWorld,
    State,
    action_at,
    action_count,
    is_legal,
    successor,
)
from csql_sim.envs.numeric import check_observation, numeric_observation, numeric_space
from csql_sim.envs.problem import PROBLEM_OPTION, EnvTask, problem_task, state_task
from csql_sim.envs.relational import MAX_MESSAGE_BLOCKS, check_env_blocks, large_mask, large_option, large_task
from csql_sim.envs.render_mode import check_render_mode
from csql_sim.infra.errors import CsqlError
from csql_sim.learners.paper import StepLearner, Transition


def rule_transitions(world: BlocksWorld, rules: str | os.PathLike) -> np.ndarray:
    """``[state, action]`` -> next state index (-1: illegal): the rule file's world model's table."""
    base = load(rules)
    if base.blocks != world.n:
        raise CsqlError(f"{rules}: rules for {base.blocks} blocks, the environment has {world.n}")
    model = WorldModel([c for c in base.classifiers if isinstance(c, (PreconditionRule, AddDeleteRule))], world.n)
    try:
        return model.table.next_state
    except CsqlError as exc:
        raise CsqlError(f"{rules}: {exc}") from None


def check_max_steps(max_steps: object) -> int | None:
    """``max_steps`` of an environment: None (never truncate) or a positive integer, else a CsqlError."""
    if max_steps is None:
        return None
    if isinstance(max_steps, (int, np.integer)) and not isinstance(max_steps, bool) and max_steps >= 1:
        return int(max_steps)
    raise CsqlError(f"max_steps must be None or a positive integer, got {max_steps!r}")


RESET_OPTIONS = ("start", "goal", PROBLEM_OPTION)
"""The keys ``reset(options=...)`` reads; any other is a ValueError (CsqlError) naming it."""


def check_options(options: object) -> dict:
    """``reset``'s ``options``: a dict (or None, read as empty), else a CsqlError."""
    if options is None:
        return {}
    if not isinstance(options, dict):
        raise CsqlError(f"options must be a dict or None, got {type(options).__name__} {options!r:.80}")
    unknown = sorted(repr(k)[:60] for k in options if k not in RESET_OPTIONS)
    if unknown:
        raise CsqlError(f"unknown reset option {', '.join(unknown[:3])}; the options are {', '.join(RESET_OPTIONS)}")
    return options


class EnvEpisode(NamedTuple):
    """One episode on an environment: steps taken and whether the goal was reached."""

    steps: int
    reached: bool


class BlocksWorldEnv(gym.Env):
    """Gymnasium environment of the symbolic n-block world with the paper's messages.

    Registered as ``csql_sim/BlocksWorld-v0``:
    ``gymnasium.make("csql_sim/BlocksWorld-v0", blocks=4, rules=None, render_mode="ansi")``.

    ## Description
    n labelled blocks on a table and a one-block gripper. A task is a start and a goal
    configuration; the agent moves blocks with the four STRIPS operators until the
    configuration is the goal. The dynamics are those of the R-classifiers (the paper's
    Figure 5 for n = 3, generated from the operators otherwise, or read from ``rules``):
    the precondition rules say which actions are legal, the add-delete rules what
    follows.

    ## Action Space
    ``Discrete(len(all_actions(n)))`` (18 for n = 3, 50 for n = 5); action ``i`` has the
    paper's action code ``i + 1``, in the order unstack(X,Y), pickup(X), putdown(X),
    stack(X,Y). ``info["action_mask"]`` (int8, 1 = legal) marks the legal ones; an
    illegal action leaves the state unchanged (as LT-QL assumes) and sets
    ``info["illegal"]``.

    ## Observation Space
    ``Text`` of fixed length. For n <= 6 (16 characters for n = 2, 3; 17 for n = 4; 18
    for n = 5; 19 for n = 6) the paper's state message, e.g. ``S0111000ttt0000C``: tag,
    action slot, clear flags, what each block stands on, the held block, and the goal
    state's code. For n = 7..26 the relational form
    (:func:`~csql_sim.core.state.relational_message.format_large_message`, ``3n + 5``
    characters: 26 for n = 7, 35 for n = 10), e.g. ``S001111111_______0fg0_a_ec`` for
    ``A,B,C,D,E,F,G`` towards ``D,FAEGB+C``: tag, a two-digit action slot (``00``: none),
    the clear flags, what each block stands on
    (``a``-``j`` a block, ``_`` the table, ``0`` held), the held block (``0`` none), then
    the goal's on field and hand, written out (no goal index: the world is not enumerated).

    With ``observation="numeric"``, a ``Dict`` of integer arrays instead
    (:mod:`csql_sim.envs.numeric`): ``"on"`` and ``"goal"`` (``MultiDiscrete([n + 2] * n)``,
    what each block stands on: 0 the table, ``k`` block ``k``, ``n + 1`` the hand) and
    ``"hand"`` (``Discrete(n + 1)``, 0 empty), the spaces Stable-Baselines3 accepts.

    ## Starting State
    ``reset(options={"start": ..., "goal": ...})`` takes each as
    - for n <= 6: a :class:`~csql_sim.core.state.world.State`, a configuration (``"CBA"``:
      A on B on C) or a state index;
    - for n = 7..30: a :class:`~csql_sim.core.state.world.State`, a
      configuration with names A..Z, AA, ... (``"JIHGFEDCBA"``, ``"A,B,CD+E"``) or a rank in
      ``0..state_count(n) - 1`` (:func:`~csql_sim.core.state.state_count.unrank_state`);
    either missing is drawn uniformly from ``np_random`` (past six by counting:
    :func:`~csql_sim.core.state.state_count.sample_state`), distinct from the other.

    ``reset(options={"problem": path})`` instead reads a blocks-world PDDL problem file (or
    takes a :class:`~csql_sim.core.files.pddl_import.BlocksProblem`) of exactly n objects, as
    ``csql-sim execute --problem`` does (:mod:`csql_sim.envs.problem`): its initial state is
    the start, its goal may be *partial* (atoms that leave blocks free), and its object names
    are the blocks' names. Sorted by name (``b2`` before ``b10``), object ``i`` is block ``i``
    (cube A, B, ...). The goal state in the observation is one satisfying state (the nearest
    to the start). Not with ``start`` or ``goal``; a problem of another size, a file that
    cannot be read, or a start that already satisfies the goal is a one-line CsqlError.

    ## Rewards
    1 on the step that reaches the goal, 0 otherwise.

    ## Episode End
    - Termination: the state is the goal; with a ``problem``, the state satisfies the goal's
      atoms (any satisfying state, not only the one the observation shows).
    - Truncation: ``max_steps`` steps have been taken (never when ``max_steps`` is None).
      ``gymnasium.make`` also wraps it in a ``TimeLimit`` of
      :data:`~csql_sim.envs.registration.MAX_EPISODE_STEPS` steps unless given
      ``max_episode_steps``.

    ## Information
    ``reset`` and ``step`` return ``action_mask``, ``state`` and ``goal`` (as
    :class:`~csql_sim.core.state.world.State`), ``illegal``, ``names`` (the blocks' names,
    block 0 first: a ``problem``'s objects as written in it, else ``A``, ``B``, ...) and
    ``goal_atoms`` (the goal in PDDL atoms with those names). :meth:`action_name` writes an
    action with the names (``unstack(jade,Ruby)``), and ``render`` shows the state with them.

    ## Seeding
    ``reset(seed=s)`` seeds ``np_random`` (Gymnasium's contract); from it a missing goal
    and then a missing start are drawn, nothing else: the dynamics are deterministic. So
    the same seed and options give the same task, and the same actions the same
    observations, in any process. A later ``reset()`` without a seed continues the
    stream; the first ``reset()`` of an env never seeded draws fresh entropy.

    Args:
        n: number of blocks, 2..30 (``blocks`` in ``gymnasium.make``; past 26 the observation is numeric).
        max_steps: steps before ``truncated``: a positive integer, or None (never).
        render_mode: ``"ansi"`` (the state's notation, in the blocks' names, and message) or None; any other mode
            raises ``gymnasium.error.UnsupportedMode``.
        rules: a rule file whose R-classifiers define the dynamics (default: the
            built-in ones, identical to the blocks world); Q-classifiers in it are ignored.
            n <= 6 only: past six the dynamics are the four operators on relational states.
        observation: ``"message"`` (the default: the state message, a ``Text``) or
            ``"numeric"`` (a ``Dict`` of integer arrays, :mod:`csql_sim.envs.numeric`).

    """

    metadata = {"render_modes": ["ansi"], "render_fps": 4}

    def __init__(self, n: int = 3, max_steps: int | None = None, render_mode: str | None = None,
                 rules: str | os.PathLike | None = None, observation: str = "message") -> None:
        self.n = check_env_blocks(n)
        self.large = self.n > MAX_BLOCKS
        self.max_steps = check_max_steps(max_steps)
        self.observation = check_observation(observation)
        if self.n > MAX_MESSAGE_BLOCKS and self.observation != "numeric":
            raise CsqlError(f"state messages write at most {MAX_MESSAGE_BLOCKS} blocks; for {self.n} give "
                            f"observation='numeric'")
        check_render_mode(render_mode, self.metadata["render_modes"])
        if self.large and rules is not None:
            raise CsqlError(f"rules define the dynamics up to {MAX_BLOCKS} blocks; past six the environment applies "
                            f"the four operators to relational states (give no rules)")
        self.render_mode = render_mode
        self.observation_space = numeric_space(self.n) if self.observation == "numeric" else self._text_space()
        self.action_space = gym.spaces.Discrete(action_count(self.n))
        self.rules = rules
        self.world = None if self.large else BlocksWorld.of(self.n)
        if self.world is not None:
            table = true_table(n).next_state if rules is None else rule_transitions(self.world, rules)
            self.next_state = table.tolist()
            self._masks = list((table >= 0).astype(np.int8))
        self.state: Any = 0  # a state index; past six a State
        self.goal: Any = 1
        self.task: EnvTask | None = None  # set by reset: the goal's atoms and the blocks' names
        self._goal_atoms: tuple[str, ...] = ()
        self.steps = 0

    def _text_space(self) -> gym.spaces.Text:
        length = message_length(self.n) if self.large else layout(self.n).length
        return gym.spaces.Text(min_length=length, max_length=length, charset=frozenset(DIGITS + DIGITS.lower() + "S#_"))

    @property
    def current(self) -> State:
        """The current state (what the last observation shows)."""
        return self.state if self.large else self.world.states[self.state]

    @property
    def target(self) -> State:
        """The goal state."""
        return self.goal if self.large else self.world.states[self.goal]

    def _set_current(self, state: State) -> None:
        self.state = state if self.large else self.world.state_index(state)

    def _action(self, action: int) -> Action:
        """The action of index ``action`` (the stable action order)."""
        return action_at(int(action), self.n) if self.large else self.world.actions[int(action)]

    def _legal(self, action: int) -> bool:
        if self.large:
            return is_legal(self.state, self._action(action))
        return self.next_state[self.state][int(action)] >= 0

    def _index(self, value: Any, name: str) -> int:
        if isinstance(value, State):
            return self.world.state_index(value)
        if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
            if not 0 <= int(value) < len(self.world.states):
                raise CsqlError(f"{name} index {value} out of range 0..{len(self.world.states) - 1}")
            return int(value)
        if isinstance(value, str):
            return self.world.state_index(parse_config(value, self.n))
        raise CsqlError(f"{name} must be a State, a configuration or an index, got {value!r}")

    def _obs(self) -> Any:
        if self.observation == "numeric":
            return numeric_observation(self.current, self.target)
        if self.large:
            return format_large_message(self.state, self.goal)
        return format_state_message(self.world.states[self.state], self.goal)

    @property
    def names(self) -> tuple[str, ...]:
        """The blocks' names: a ``problem``'s objects as written in it, else A, B, ..."""
        return self.task.names if self.task is not None else default_names(self.n)

    def action_name(self, action: int) -> str:
        """Action ``action`` (an index) as text with the blocks' names, e.g. ``unstack(jade,Ruby)``."""
        if not self.action_space.contains(action):
            raise CsqlError(f"action must be 0..{self.action_space.n - 1}, got {action!r}")
        return self._action(action).name(self.names)

    def _info(self, illegal: bool = False) -> dict:
        mask = large_mask(self.state) if self.large else self._masks[self.state].copy()
        return {"action_mask": mask, "state": self.current, "goal": self.target, "illegal": illegal,
                "names": self.names, "goal_atoms": self._goal_atoms}

    def _reached(self) -> bool:
        """Whether the current state ends the episode (satisfies the goal's atoms)."""
        return self.task is not None and self.task.satisfied(self.current)

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[str, dict]:
        """Start a task; ``options`` may give ``start`` and ``goal``, or a ``problem``."""
        options = check_options(options)
        super().reset(seed=seed)
        if options.get(PROBLEM_OPTION) is not None:
            self.task = task = problem_task(options[PROBLEM_OPTION], self.n, options)
            self.state, self.goal = ((task.start, task.target) if self.large else
                                     (self.world.state_index(task.start), self.world.state_index(task.target)))
        else:
            self.state, self.goal = self._draw(options)
            self.task = state_task(self.current, self.target)
        self._goal_atoms = self.task.goal_atoms()
        self.steps = 0
        return self._obs(), self._info()

    def _draw(self, options: dict) -> tuple[Any, Any]:
        """Start and goal from the ``start`` and ``goal`` options, each missing one drawn (see Seeding)."""
        if self.large:
            start, goal = (None if options.get(k) is None else large_option(options[k], self.n, k)
                           for k in ("start", "goal"))
            return large_task(self.np_random, self.n, start, goal)
        count = len(self.world.states)
        start = self._index(options["start"], "start") if options.get("start") is not None else None
        goal = self._index(options["goal"], "goal") if options.get("goal") is not None else None
        if goal is None:
            goal = int(self.np_random.integers(count))
            if start is not None and goal == start:
                goal = (goal + 1 + int(self.np_random.integers(count - 1))) % count
        if start is None:
            start = int(self.np_random.integers(count - 1))
            start += start >= goal
        if start == goal:
            raise CsqlError(f"start and goal are the same state {self.world.states[start].notation()}")
        return start, goal

    def step(self, action: int) -> tuple[str, float, bool, bool, dict]:
        """Apply ``action`` (an index); an illegal one leaves the state unchanged."""
        if not self.action_space.contains(action):
            raise CsqlError(f"action must be 0..{self.action_space.n - 1}, got {action!r}")
        illegal = not self._legal(action)
        if not illegal:
            self.state = successor(self.state, self._action(action)) if self.large \
                else self.next_state[self.state][int(action)]
        self.steps += 1
        terminated = self._reached()
        truncated = not terminated and self.max_steps is not None and self.steps >= self.max_steps
        return self._obs(), 1.0 if terminated else 0.0, terminated, truncated, self._info(illegal)

    def render(self) -> str | None:
        """``ansi``: the state's notation and its message."""
        if self.render_mode == "ansi":
            shown = self.current.named(self.names).named_notation()
            if self.n > MAX_MESSAGE_BLOCKS:
                return shown
            message = format_large_message(self.state, self.goal) if self.large \
                else format_state_message(self.world.states[self.state], self.goal)
            return f"{shown}  {message}"
        return None


def run_env_episode(env: gym.Env, learner: StepLearner, temperature: float, options: dict | None = None,
                    cap: int | None = None, seed: int | None = None) -> EnvEpisode:
    """Let ``learner`` act on ``env`` for one episode, learning from the observed transitions.

    Each step: the learner acts on the observation (one uniform from its stream, as in
    training), the environment steps, and the learner learns from what was observed.
    Works with any step learner and any environment with this interface, symbolic or physical.

    Args:
        env: a blocks-world environment (observations are state messages).
        learner: any :class:`~csql_sim.learners.paper.trial.StepLearner` (a reference engine).
        temperature: T of eq. 3 (0 = greedy).
        options: passed to ``env.reset`` (``start`` and ``goal``, or ``problem``).
        cap: the most steps (default ``learner.params.step_cap``).
        seed: passed to ``env.reset``; with it the episode is fully determined (see the
            environment's seeding contract).

    """
    observation, _info = env.reset(seed=seed, options=options)
    cap = learner.params.step_cap if cap is None else cap
    learner.begin_episode()
    for steps in range(1, cap + 1):
        action = learner.act(observation, temperature)
        nxt, _reward, terminated, truncated, _info = env.step(action)
        learner.learn(Transition(observation, action, nxt, terminated))
        if terminated or truncated:
            return EnvEpisode(steps, terminated)
        observation = nxt
    return EnvEpisode(cap, False)
