"""The arm's tower limit: how tall a tower a task needs, and the refusal of taller ones.

:data:`~csql_sim.sim.world.config.MAX_TOWER_HEIGHT` is the tallest tower the arm builds
and takes apart (measured by ``benchmarks/arm_thirty.py --towers``). A task whose start,
goal or plan needs a taller tower is refused with one line before any physics runs.
"""

from __future__ import annotations

from collections.abc import Iterable

from csql_sim.core.model.goal_spec import GoalSpec
from csql_sim.core.state.state import State
from csql_sim.sim.world.arm_state import SimError
from csql_sim.sim.world.config import MAX_TOWER_HEIGHT


def tower_height(state: State) -> int:
    """The height of the state's tallest tower (cubes; a held cube counts as a tower of one)."""
    return max([len(t) for t in state.towers()] + [1 if state.held is not None else 0])


def goal_height(goal: GoalSpec | State) -> int:
    """The tallest tower a goal needs: its tallest tower, or a partial goal's longest chain of ``on`` atoms."""
    if isinstance(goal, State):
        return tower_height(goal)
    below = {args[0]: args[1] for pred, args in goal.positive if pred == "on" and len(args) == 2}
    best = 1 if goal.positive else 0
    for block in below:
        seen, height, x = {block}, 1, block
        while x in below and below[x] not in seen:
            x = below[x]
            seen.add(x)
            height += 1
        best = max(best, height)
    return best


TALL_TOWER = 5
"""A tower of this many cubes or more reaches the forearm housing's height beside a hand at the table."""


def tall_bases(goal: State, height: int = TALL_TOWER) -> frozenset[int]:
    """The bottom cubes of the goal's towers of ``height`` cubes or more."""
    return frozenset(t[0] for t in goal.towers() if len(t) >= height)


def check_tower_heights(start: State, goal: GoalSpec | State, plan: Iterable[State] = (),
                        limit: int = MAX_TOWER_HEIGHT) -> None:
    """Refuse, with one line, a task whose start, goal or planned states need a tower taller than ``limit``."""
    for what, height in (("start", tower_height(start)), ("goal", goal_height(goal))):
        if height > limit:
            raise SimError(f"the {what} has a tower of {height} cubes; the arm builds and takes apart towers of "
                           f"at most {limit}")
    for k, state in enumerate(plan):
        if tower_height(state) > limit:
            raise SimError(f"the plan builds a tower of {tower_height(state)} cubes (after step {k}); the arm "
                           f"builds and takes apart towers of at most {limit}")


__all__ = ["check_tower_heights", "goal_height", "tower_height"]
