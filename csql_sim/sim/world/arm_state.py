"""States on the arm: the enumerated world's (n <= 6) or relational ones (7..30 cubes).

For n <= 6 the arm works on :class:`csql_sim.core.state.world.State`, with the paper's message
form (goal by its index), BFS optima and the ground R-classifiers, exactly as before. For
7..30 cubes (:data:`~csql_sim.sim.world.config.MAX_ARM_BLOCKS`) the states are
:class:`csql_sim.core.state.state.State` records: messages take the large form
(:func:`csql_sim.core.state.relational_message.format_large_message`; past 26 cubes there is
no message, and the policy reads the state), optimal lengths come from
:func:`csql_sim.core.measure.optimum.optimal_length` (measuring only), the world model interprets
the lifted rules (:class:`RelationalWorldModel`), and the policy must be lifted (BFS and
ground rule files enumerate the world: refused). Every name here is the same function of
the state for both kinds, so the rest of the simulator need not ask which one it has.
"""

from __future__ import annotations

from typing import Any

from csql_sim.core.classifiers.lifted_rule import BLOCKS_WORLD
from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model.lifted_model import LiftedWorldModel
from csql_sim.core.model.search import distance
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.state.message import action_code, format_state_message
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.relational_message import MAX_LARGE_MESSAGE, format_large_message
from csql_sim.core.state.state import default_name
from csql_sim.core.state.world import (
    MAX_BLOCKS,
    MIN_BLOCKS,
    Action,
    BlocksWorld,
    State,
    WorldError,
    action_name,
)
from csql_sim.infra.errors import CsqlError
from csql_sim.sim.world.config import MAX_ARM_BLOCKS

ArmState = State
"""A state the arm can build and perceive (2..30 cubes)."""


class SimError(CsqlError):
    """A physical world that cannot be built or a bad simulation option."""


def check_arm_blocks(n: int) -> int:
    """``n`` if the arm can hold that many cubes (2..30), else a SimError saying why not."""
    if not isinstance(n, int) or isinstance(n, bool) or n < MIN_BLOCKS:
        raise SimError(f"number of cubes must be {MIN_BLOCKS}..{MAX_ARM_BLOCKS}, got {n!r}")
    if n > MAX_ARM_BLOCKS:
        raise SimError(f"the arm takes at most {MAX_ARM_BLOCKS} cubes (the table's ring has {MAX_ARM_BLOCKS} places "
                       f"within the Panda's reach), got {n}")
    return n


def is_large(n: int) -> bool:
    """Whether n cubes are past the enumerated world (relational states, the large message form)."""
    return n > MAX_BLOCKS


def letter(i: int) -> str:
    """The name of cube ``i``: A..Z, then AA, AB, ... (:func:`csql_sim.core.state.state.default_name`)."""
    return default_name(i)


def label(action: Action) -> str:
    """The action's name with letters past F (``stack(J,I)``); the same as ``Action.name`` for A-F."""
    return action_name(action)


def arm_state(support: tuple[int, ...]) -> ArmState:
    """The state with these supports (raises WorldError if invalid)."""
    return State(support)


def to_arm_state(state: State) -> ArmState:
    """``state`` as the arm's kind (one State for every n)."""
    return state


def parse_arm_state(text: str, n: int | None = None) -> ArmState:
    """A configuration in the notation (``JIHGFEDCBA``, ``A,B+C``) as the arm's kind of state.

    It is read as :func:`csql_sim.core.state.notation.parse_config` reads it (the same errors).
    """
    return parse_config(text, n)


def arm_optimal_length(start: ArmState, goal: ArmState) -> int:
    """The optimal plan length (four operators): BFS for n <= 6, the exact optimum past six (measuring only)."""
    if start.n != goal.n:
        raise WorldError(f"start has {start.n} blocks but goal has {goal.n}")
    if not is_large(start.n):
        return distance(start, goal)
    return optimal_length(start, goal)


class Messages:
    """The state messages of one task's goal: the paper's form for n <= 6, the large form to 26, none (``""``) past."""

    def __init__(self, goal: ArmState) -> None:
        self.goal = goal
        self.n = goal.n
        self.goal_index = None if is_large(goal.n) else BlocksWorld.of(goal.n).state_index(goal)

    def state(self, state: ArmState, action: Action | None = None) -> str:
        """The message of ``state`` towards the goal, with ``action``'s code in the action slot (empty: None)."""
        if self.goal_index is None:
            return "" if self.n > MAX_LARGE_MESSAGE else format_large_message(state, self.goal, action)
        code = 0 if action is None else int(action_code(action, self.n), 36)
        return format_state_message(state, self.goal_index, code)


class RelationalWorldModel:
    """The executor's world-model interface for 7..30 cubes: the lifted rules, read on relational states.

    :class:`csql_sim.core.model.world_model.WorldModel` grounds R-classifiers into messages of
    the enumerated world; past six blocks the same four schemas are interpreted directly
    (:class:`csql_sim.core.model.lifted_model.LiftedWorldModel`). ``goal`` arguments are accepted
    for the same call shape and ignored (the rules do not read the goal).
    """

    def __init__(self, model: LiftedWorldModel | None = None) -> None:
        self.model = model or LiftedWorldModel(BLOCKS_WORLD)

    def is_legal(self, state: State, action: Action, goal: Any = 0) -> bool:
        """Whether the rules allow ``action`` in ``state``."""
        return self.model.is_legal(state, action)

    def predict_state(self, state: State, action: Action, goal: Any = 0) -> State:
        """The state the rules predict after ``action``."""
        return self.model.successor(state, action)


def world_model_for(n: int) -> WorldModel | RelationalWorldModel:
    """The built-in world model of n cubes: the ground R-classifiers (n <= 6) or the lifted rules."""
    return WorldModel.for_blocks(n) if not is_large(n) else RelationalWorldModel()


def check_arm_policy(policy: object | None, n: int) -> None:
    """Refuse, with one line, a policy that cannot plan past six blocks: BFS (None) or a ground rule table."""
    if not is_large(n):
        return
    if policy is None or getattr(policy, "name", "") == "bfs":
        raise SimError(f"BFS enumerates the world and plans only up to {MAX_BLOCKS} blocks; for {n} cubes give a "
                       f"lifted policy (lifted rules, or the gn1 baseline)")
    blocks = getattr(policy, "blocks", None)
    if blocks is not None:
        raise SimError(f"a ground rule base is for {blocks} blocks only; for {n} cubes give a lifted policy "
                       f"(lifted rules, or the gn1 baseline)")


__all__ = ["ArmState", "Messages", "RelationalWorldModel", "SimError", "arm_optimal_length", "arm_state",
           "check_arm_blocks", "check_arm_policy", "is_large", "label", "letter", "parse_arm_state",
           "to_arm_state", "world_model_for"]
