"""What the top-level API returns: frozen records in the problem's own names.

Every record is a frozen dataclass whose fields are plain Python values (strings,
integers, tuples), so it prints, compares and serializes without the package's internals;
the job's full report rides along in a field that is neither printed nor compared.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from csql_sim.core.files.ipc_plan import ipc_lines_text
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import write_atomic

ActionTuple = tuple[str, ...]
"""One action as the problem's domain names it: ``("unstack", "amber", "pearl")``."""


def action_tuple(line: str) -> ActionTuple:
    """An IPC plan line, ``(unstack amber pearl)``, as a tuple of its words."""
    return tuple(line.strip().strip("()").split())


def action_line(action: ActionTuple) -> str:
    """A tuple of words as an IPC plan line (the inverse of :func:`action_tuple`)."""
    return "(" + " ".join(action) + ")"


@dataclass(frozen=True)
class Plan:
    """A plan for a PDDL problem, or why there is none.

    Attributes:
        problem: the problem's name (its ``(problem ...)``).
        objects: the blocks' names, as the file spells them.
        actions: the plan, each action a tuple in the domain's words and the problem's names,
            ``("unstack", "amber", "pearl")``; empty when not solved.
        solved: whether the plan reaches the goal.
        planner: who planned: ``builtin`` (the shipped lifted rules), ``rules`` (a rule file),
            ``bfs`` or ``gn1``.
        optimal_length: the optimal plan length when it is known exactly (breadth-first search
            up to six blocks; past six a proven bound within ``optimum_budget``), else None.
        lower_bound: 2 x the misplaced blocks (a lower bound on any plan), or None.
        reason: why it is not solved ("" when solved).
        seconds: reading and planning time (not measuring).
    """

    problem: str
    objects: tuple[str, ...]
    actions: tuple[ActionTuple, ...]
    solved: bool
    planner: str
    optimal_length: int | None = None
    lower_bound: int | None = None
    reason: str = ""
    seconds: float = field(default=0.0, compare=False)
    report: Any = field(default=None, repr=False, compare=False)

    @property
    def length(self) -> int:
        """The number of actions."""
        return len(self.actions)

    @property
    def lines(self) -> tuple[str, ...]:
        """The plan as IPC lines, ``(unstack amber pearl)``."""
        return tuple(action_line(a) for a in self.actions)

    def text(self) -> str:
        """The plan file's text, as Fast Downward writes it (one action a line, then the cost)."""
        return ipc_lines_text(self.lines)

    def write(self, path: str | os.PathLike, overwrite: bool = False) -> Path:
        """Write the plan file (atomically; an existing file only with ``overwrite``); returns its path."""
        if not overwrite and os.path.lexists(path):
            raise CsqlError(f"{os.fspath(path)} exists; pass overwrite=True to replace it")
        return write_atomic(path, self.text())


@dataclass(frozen=True)
class Validation:
    """The verdict on a plan, checked symbolically from the problem's start.

    Attributes:
        valid: every step is applicable and the plan ends in a goal state.
        steps: the plan's steps (its action lines).
        errors: one line per error (empty when valid): the first step whose precondition fails
            (its number, its line, the precondition and why), or each goal atom that does not
            hold at the end.
        applied: how many steps applied before the first that does not (all of them when none fails).
        final: the state after the steps that applied, in the problem's names.
    """

    valid: bool
    steps: int
    errors: tuple[str, ...] = ()
    applied: int = 0
    final: str = ""
    report: Any = field(default=None, repr=False, compare=False)

    def __bool__(self) -> bool:
        return self.valid


@dataclass(frozen=True)
class Execution:
    """A plan run on the simulated arm, closed loop; the goal judged from perception.

    Attributes:
        reached: the final **perceived** state satisfies the goal.
        reason: why not ("" when reached).
        actions: the number of arm actions run.
        final: the final perceived state in the problem's names, or None if nothing was perceived.
        video: the video written, or None.
        objects: the blocks' names, as the file spells them.
    """

    reached: bool
    reason: str
    actions: int
    final: str | None
    video: Path | None
    objects: tuple[str, ...]
    report: Any = field(default=None, repr=False, compare=False)


@dataclass(frozen=True)
class LiftedRules:
    """Lifted Q-classifiers learned by :func:`csql_sim.api.train_lifted`.

    Attributes:
        path: the file written (``out``), or None when it was not asked for.
        text: the rule file's JSON text (what :func:`csql_sim.api.plan` reads as ``rules``).
        classifiers: the learned classifiers in words (a committee's members one after another).
        trials: training trials run (summed over a committee's members).
        seconds: training time.
    """

    path: Path | None
    text: str = field(repr=False)
    classifiers: tuple[str, ...]
    trials: int
    seconds: float = field(compare=False)
    runs: tuple[Any, ...] = field(default=(), repr=False, compare=False)
    meta: dict = field(default_factory=dict, repr=False, compare=False)


__all__ = ["ActionTuple", "Execution", "LiftedRules", "Plan", "Validation", "action_line", "action_tuple"]
