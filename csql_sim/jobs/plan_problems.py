"""Planning blocks-world PDDL problems of any size: one file, or every problem of a folder.

A problem (:func:`csql_sim.core.files.pddl_import.read_problem`, up to
:data:`~csql_sim.core.files.pddl_import.MAX_PLANNED_BLOCKS` objects) is planned towards its
target (:func:`csql_sim.core.model.goal_spec.goal_target`: the goal's state, or for a partial
goal the goal with every free block well placed where it stands). Up to six blocks the
ground rollout plans; past six the relational one (lifted rules, GN1). Plans are written in
the problem's own words (:mod:`csql_sim.core.files.plan_spelling`).

Measuring comes after planning and never feeds it: the lower bound (2 x the misplaced
blocks) and the optimum to the target, exact by breadth-first search up to six blocks,
else by :func:`csql_sim.core.measure.bounds.bounded_optimum` within a time budget (proven or
bounded; a budget of 0 skips it: "not measured"). Neither is measured where the start or
the target holds a block.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

from csql_sim.core.files.pddl_import import MAX_PLANNED_BLOCKS, BlocksProblem, read_problem
from csql_sim.core.files.plan_spelling import spelled_plan_lines, spelling_of
from csql_sim.core.measure.bounds import Bound, bounded_optimum, lower_bound
from csql_sim.core.model.goal_spec import goal_target
from csql_sim.core.policies.policy import Policy
from csql_sim.core.policies.relational_rollout import RelationalPolicy
from csql_sim.core.state.world import MAX_BLOCKS, Action, State, WorldError
from csql_sim.infra.errors import CsqlError
from csql_sim.jobs.execute_batch import problem_files

PolicyFor = Callable[[int], "Policy | RelationalPolicy"]
"""The planner for a task of n blocks (raises CsqlError where it cannot plan n)."""


@dataclass(frozen=True)
class ProblemPlan:
    """One planned problem (or why not).

    Attributes:
        problem: the file's path.
        blocks: its number of blocks (None when it could not be read).
        planner: who planned.
        solved: whether the plan reaches the goal.
        actions: the plan (four operators), empty when unsolved.
        lines: the plan file's lines, in the problem's words.
        seconds: reading and planning (not measuring).
        lower_bound: 2 x the misplaced blocks, or None (not measured).
        optimum: the optimum to the target (proven or bounded), or None (not measured).
        reason: why it is unsolved ("" when solved).
        partial: whether the goal is partial.
        problem_doc: the problem (names, start, goal) when it was read.
    """

    problem: str
    blocks: int | None
    planner: str
    solved: bool
    actions: tuple[Action, ...] = ()
    lines: tuple[str, ...] = ()
    seconds: float = 0.0
    lower_bound: int | None = None
    optimum: Bound | None = None
    reason: str = ""
    partial: bool = False
    problem_doc: BlocksProblem | None = field(default=None, repr=False, compare=False)

    def row(self) -> dict:
        """The JSON row of a ``--problems`` report."""
        opt = self.optimum
        return {"problem": self.problem, "blocks": self.blocks, "planner": self.planner, "solved": self.solved,
                "cost": len(self.actions) if self.solved else None, "seconds": round(self.seconds, 4),
                "lower_bound": self.lower_bound, "partial": self.partial,
                "optimum": None if opt is None else {"lower": opt.lower, "upper": opt.upper, "proven": opt.proven,
                                                     "method": opt.method},
                "reason": self.reason}


def read_blocks_problem(path: str | os.PathLike, domain: str | os.PathLike | None = None) -> BlocksProblem:
    """A problem file of up to :data:`MAX_PLANNED_BLOCKS` blocks (PddlImportError naming the file)."""
    return read_problem(path, domain, max_blocks=MAX_PLANNED_BLOCKS)


def _rollout(policy: Policy | RelationalPolicy, start: State, target: State) -> tuple[tuple[Action, ...], bool, str]:
    if start.n <= MAX_BLOCKS:
        from csql_sim.core.policies.rollout import rollout

        ground = rollout(policy, start, target)
        return tuple(ground.actions), ground.reached, ground.reason
    from csql_sim.core.policies.relational_rollout import rollout_relational

    run = rollout_relational(policy, start, target)
    return run.actions, run.reached, run.reason


def measure(start: State, target: State, length: int | None, budget_s: float) -> tuple[int | None, Bound | None]:
    """The lower bound and the optimum from ``start`` to ``target`` (None: not measured)."""
    if start.held is not None or target.held is not None:
        return None, None
    lower = lower_bound(start, target)
    if start.n <= MAX_BLOCKS:
        from csql_sim.core.model.search import distance

        exact = distance(start, target)
        return lower, Bound(exact, exact, "breadth-first search")
    if budget_s <= 0:
        return lower, None
    return lower, bounded_optimum(start, target, budget_s, upper=length)


def plan_problem(path: str | os.PathLike, domain: str | os.PathLike | None, policy_for: PolicyFor,
                 planner: str, budget_s: float, blocks: BlocksProblem | None = None) -> ProblemPlan:
    """Read, plan and measure one problem file; CsqlError (one line) where it cannot be read or planned.

    ``blocks``: the problem already read (from its text): ``path`` and ``domain`` then only name it.
    """
    began = time.perf_counter()
    problem = read_blocks_problem(path, domain) if blocks is None else blocks
    start, target = problem.start, goal_target(problem.goal, problem.start)
    policy = policy_for(problem.n)
    actions, solved, reason = _rollout(policy, start, target)
    seconds = time.perf_counter() - began
    lines: tuple[str, ...] = ()
    if solved:
        if not problem.goal.satisfied(_end(start, actions)):
            raise WorldError(f"{os.fspath(path)}: the plan reaches its target but not the goal")  # a bug, not a task
        lines = tuple(spelled_plan_lines(actions, spelling_of(problem)))
    lower, optimum = measure(start, target, len(actions) if solved else None, budget_s) if solved else (None, None)
    return ProblemPlan(os.fspath(path), problem.n, planner, solved, actions if solved else (), lines, seconds,
                       lower, optimum, reason, problem.goal.partial, problem)


def _end(start: State, actions: tuple[Action, ...]) -> State:
    from csql_sim.core.state.world import successor

    state = start
    for action in actions:
        state = successor(state, action)
    return state


def iter_folder(folder: str | os.PathLike, domain: str | os.PathLike | None, policy_for: PolicyFor,
                planner: str, budget_s: float) -> Iterator[ProblemPlan]:
    """Every problem of ``folder`` (sorted; domain files skipped), each as it is planned.

    A problem that cannot be read or planned (a CsqlError, a WorldError) is a failed row naming
    its file, and the folder's other problems still run.
    """
    for path, unreadable in problem_files(folder):
        if unreadable is not None:
            yield ProblemPlan(os.fspath(path), None, planner, False, reason=unreadable)
            continue
        try:
            yield plan_problem(path, domain, policy_for, planner, budget_s)
        except CsqlError as exc:
            yield ProblemPlan(os.fspath(path), None, planner, False, reason=_named(str(exc), path))


def plan_folder(folder: str | os.PathLike, domain: str | os.PathLike | None, policy_for: PolicyFor,
                planner: str, budget_s: float) -> list[ProblemPlan]:
    """:func:`iter_folder` as a list."""
    return list(iter_folder(folder, domain, policy_for, planner, budget_s))


def _named(message: str, path: Path) -> str:
    """``message``, naming the file if it does not already."""
    return message if os.fspath(path) in message or path.name in message else f"{path}: {message}"
