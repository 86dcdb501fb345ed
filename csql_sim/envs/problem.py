"""The ``problem`` reset option of the environments: a PDDL problem as the task.

``env.reset(options={"problem": "blocks12.pddl"})`` reads a blocks-world PDDL problem
(:func:`~csql_sim.core.files.pddl_import.read_problem`, as ``csql-sim execute --problem``
does): its initial state is the start, its goal (full or *partial*: a conjunction of
atoms that leaves some blocks free) decides termination, and its object names are the
blocks' names. Object ``i`` in the sorted order of the names (``b2`` before ``b10``) is
block ``i`` (cube A, B, ...), so the observation keeps its format.

The goal state the observation shows is :meth:`~csql_sim.core.model.goal_spec.GoalSpec.nearest`
of the start (up to six blocks the satisfying state fewest actions away; past six
:func:`~csql_sim.core.model.goal_spec.goal_target`): one configuration that satisfies the
goal, which a policy may aim for. The episode terminates as soon as the (perceived) state
satisfies the goal's atoms, whichever satisfying state that is.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

from csql_sim.core.files.pddl_import import MAX_PLANNED_BLOCKS, BlocksProblem, read_problem
from csql_sim.core.model.goal_spec import GoalError, GoalSpec, atom_text, state_atoms
from csql_sim.core.state.state import default_names
from csql_sim.core.state.world import State
from csql_sim.infra.errors import CsqlError

PROBLEM_OPTION = "problem"
"""The reset option that names a PDDL problem (a path, or a read :class:`BlocksProblem`)."""


@dataclass(frozen=True)
class EnvTask:
    """A task of an environment: start, goal state shown, the goal's atoms and the blocks' names.

    Attributes:
        start: the start configuration (with the blocks' names).
        target: the goal state the observation shows (satisfies ``goal``).
        goal: the goal; None when the task is the one state ``target`` (``start``/``goal`` options).
        names: the blocks' names (the problem's objects as written, else A, B, ...).
    """

    start: State
    target: State
    goal: GoalSpec | None
    names: tuple[str, ...]

    def satisfied(self, state: State | None) -> bool:
        """Whether ``state`` ends the episode: it satisfies the goal's atoms (is the target, without a goal)."""
        if state is None:
            return False
        return self.goal.satisfied(state) if self.goal is not None else state == self.target

    def goal_atoms(self) -> tuple[str, ...]:
        """The goal in PDDL atoms with the blocks' names (without a goal, the target's atoms)."""
        if self.goal is not None:
            positive = sorted(atom_text(a, self.names) for a in self.goal.positive)
            return (*positive, *sorted(f"(not {atom_text(a, self.names)})" for a in self.goal.negative))
        return tuple(sorted(atom_text(a, self.names) for a in state_atoms(self.target)))


def state_task(start: State, target: State) -> EnvTask:
    """The task of the ``start`` and ``goal`` options: one goal state, the default names."""
    return EnvTask(start, target, None, default_names(start.n))


def problem_task(value: object, n: int, options: dict) -> EnvTask:
    """The task of ``options["problem"]`` on an environment of ``n`` blocks; a CsqlError (one line) if it is not one.

    ``value`` is a PDDL problem file's path or a read :class:`BlocksProblem`; ``start`` and
    ``goal`` may not be given with it.
    """
    both = [k for k in ("start", "goal") if options.get(k) is not None]
    if both:
        raise CsqlError(f"reset option problem gives the start and the goal; give it without {' and '.join(both)}")
    if isinstance(value, BlocksProblem):
        bp, where = value, f"problem {value.name}"
    elif isinstance(value, (str, os.PathLike)):
        bp, where = read_problem(value, max_blocks=MAX_PLANNED_BLOCKS), os.fspath(value)
    else:
        raise CsqlError(f"reset option problem must be a PDDL problem file's path, got {type(value).__name__} "
                        f"{value!r:.80}")
    if bp.n != n:
        raise CsqlError(f"{where}: the problem has {bp.n} blocks, the environment {n}")
    if bp.goal.satisfied(bp.start):
        raise CsqlError(f"{where}: the start {bp.start.named_notation()} already satisfies the goal {bp.goal.text()}")
    try:
        target = bp.goal.nearest(bp.start)
    except GoalError as exc:
        raise CsqlError(f"{where}: {exc}") from None
    return EnvTask(bp.start, target, bp.goal, bp.names)


__all__ = ["PROBLEM_OPTION", "EnvTask", "problem_task", "state_task"]
