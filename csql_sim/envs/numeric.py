"""The numeric observation of the environments: integer arrays that RL libraries take as they are.

``gymnasium.make("csql_sim/BlocksWorld-v0", blocks=4, observation="numeric")`` observes a
``Dict`` of three integer spaces (Stable-Baselines3's ``MultiInputPolicy``, CleanRL and
the like read them without a wrapper), for n blocks numbered 1..n (block 1 is cube A):

* ``"on"``: ``MultiDiscrete([n + 2] * n)``; entry ``i`` is what block ``i + 1`` stands on:
  0 the table, ``k`` in 1..n block ``k``, ``n + 1`` the hand;
* ``"goal"``: the goal state in the same code (with a PDDL ``problem``'s partial goal, the
  satisfying state nearest the start: :mod:`csql_sim.envs.problem`);
* ``"hand"``: ``Discrete(n + 1)``; 0 when the hand is empty, else the held block (1..n).

The code is the state's ``support`` shifted by one (:func:`support_code`); it is decoded
back to the same :class:`~csql_sim.core.state.world.State` by :func:`state_of_code`.
The default observation, ``"message"``, is the paper's state message (a ``Text`` space).
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from csql_sim.core.state.world import HAND, TABLE, State, WorldError
from csql_sim.infra.errors import CsqlError

OBSERVATIONS = ("message", "numeric")
"""The observations an environment offers: ``message`` (the default) or ``numeric``."""


def check_observation(observation: object) -> str:
    """``observation`` if it is one of :data:`OBSERVATIONS`, else a CsqlError naming them."""
    if isinstance(observation, str) and observation in OBSERVATIONS:
        return observation
    raise CsqlError(f"observation must be one of {', '.join(OBSERVATIONS)}, got {observation!r}")


def numeric_space(n: int) -> gym.spaces.Dict:
    """The ``Dict`` space of the numeric observation of n blocks (see the module docstring)."""
    return gym.spaces.Dict({"on": gym.spaces.MultiDiscrete(np.full(n, n + 2, dtype=np.int64)),
                            "goal": gym.spaces.MultiDiscrete(np.full(n, n + 2, dtype=np.int64)),
                            "hand": gym.spaces.Discrete(n + 1)})


def support_code(state: State) -> np.ndarray:
    """What each block stands on: 0 the table, ``k`` block ``k`` (1-based), ``n + 1`` the hand (int64)."""
    n = state.n
    return np.array([0 if s == TABLE else n + 1 if s == HAND else s + 1 for s in state.support], dtype=np.int64)


def state_of_code(code: np.ndarray) -> State:
    """The state whose :func:`support_code` is ``code`` (a CsqlError if it is not one)."""
    n = len(code)
    values = [int(v) for v in code]
    if any(not 0 <= v <= n + 1 for v in values):
        raise CsqlError(f"a support code of {n} blocks takes values 0..{n + 1}, got {values}")
    try:
        return State(tuple(TABLE if v == 0 else HAND if v == n + 1 else v - 1 for v in values))
    except WorldError as exc:
        raise CsqlError(f"{values} is not a configuration ({exc})") from None


def numeric_observation(state: State, goal: State) -> dict[str, np.ndarray | np.int64]:
    """The numeric observation of ``state`` with ``goal`` (an element of :func:`numeric_space`)."""
    held = state.held
    return {"on": support_code(state), "goal": support_code(goal), "hand": np.int64(0 if held is None else held + 1)}


__all__ = ["OBSERVATIONS", "check_observation", "numeric_observation", "numeric_space", "state_of_code",
           "support_code"]
