"""The environments past six blocks (7..30 cubes): relational states, the large message form.

Up to six blocks the environments work on the enumerated world (state indices, the
transition table of the R-classifiers). Past six they hold
:class:`~csql_sim.core.state.world.State` records and apply the four STRIPS
operators to them (:func:`~csql_sim.core.state.world.successor`); observations are
large state messages (:func:`~csql_sim.core.state.relational_message.format_large_message`),
and a task's states are given as a State, a configuration in the notation (names
A..Z, AA, ...) or a rank (:func:`~csql_sim.core.state.state_count.unrank_state`), or drawn
uniformly by counting (:func:`~csql_sim.core.state.state_count.sample_state`), or read
from a PDDL problem (the ``problem`` reset option, :mod:`csql_sim.envs.problem`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state_count import sample_state, state_count, unrank_state
from csql_sim.core.state.world import MIN_BLOCKS, State, WorldError, action_count, action_index, legal_actions
from csql_sim.infra.errors import CsqlError

MAX_ENV_BLOCKS = 30
"""The most blocks of an environment: the arm's 30 cubes (the symbolic world keeps the same bound)."""
MAX_MESSAGE_BLOCKS = 26
"""The most blocks observed as a state message (one letter a block); past it the observation is numeric."""


def check_env_blocks(n: object) -> int:
    """``n`` if an environment takes that many blocks (2..30), else a CsqlError."""
    if isinstance(n, (int, np.integer)) and not isinstance(n, bool) and MIN_BLOCKS <= n <= MAX_ENV_BLOCKS:
        return int(n)
    raise CsqlError(f"blocks must be an integer in {MIN_BLOCKS}..{MAX_ENV_BLOCKS}, got {n!r}")


def large_mask(state: State) -> np.ndarray:
    """``action_mask`` of a relational state: int8, 1 at the index of every legal action."""
    mask = np.zeros(action_count(state.n), dtype=np.int8)
    for action in legal_actions(state):
        mask[action_index(action, state.n)] = 1
    return mask


def large_option(value: Any, n: int, name: str) -> State:
    """``options["start"]`` or ``["goal"]`` past six blocks: a State, a configuration or a rank."""
    if isinstance(value, State):
        if value.n != n:
            raise CsqlError(f"{name} has {value.n} blocks, the environment {n}")
        return value
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        if not 0 <= int(value) < state_count(n):
            raise CsqlError(f"{name} rank {value} out of range 0..{state_count(n) - 1}")
        return unrank_state(int(value), n)
    if isinstance(value, str):
        try:
            return parse_config(value, n)
        except WorldError as exc:
            raise CsqlError(f"{name}: {exc}") from None
    raise CsqlError(f"{name} must be a State, a configuration or a rank, got {value!r}")


def large_task(rng: np.random.Generator, n: int, start: State | None,
               goal: State | None) -> tuple[State, State]:
    """Start and goal: the given ones, a missing goal and then a missing start drawn uniformly (distinct)."""
    if goal is None:
        goal = sample_state(n, rng)
        while start is not None and goal == start:
            goal = sample_state(n, rng)
    if start is None:
        start = sample_state(n, rng)
        while start == goal:
            start = sample_state(n, rng)
    if start == goal:
        raise CsqlError(f"start and goal are the same state {start.notation()}")
    return start, goal


__all__ = ["MAX_ENV_BLOCKS", "check_env_blocks", "large_mask", "large_option", "large_task"]
