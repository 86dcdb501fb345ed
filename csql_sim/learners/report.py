"""Pruning and Figure 6's table form."""

from __future__ import annotations

from csql_sim.classifiers import Classifier, ClassifierList, Q
from csql_sim.errors import CsqlError
from csql_sim.policy import QPolicy
from csql_sim.rulebase import RuleBase
from csql_sim.world import State, WorldError, successor

HEADER = ("T", "Condition", "Action", "Strength", "Q-value", "Age", "PredErr")


def prune(rulebase: RuleBase, threshold: float = 0.1) -> RuleBase:
    """A copy of ``rulebase`` without the Q-classifiers whose strength is below ``threshold``.

    R-classifiers are always kept.
    """
    kept = [c for c in rulebase.classifiers if c.kind != Q or c.strength >= threshold]
    meta = dict(rulebase.meta)
    meta["pruned_at"] = threshold
    return RuleBase(blocks=rulebase.blocks, classifiers=kept, meta=meta)


def count_q(rulebase: RuleBase) -> int:
    """Number of Q-classifiers in a rule base."""
    return sum(1 for c in rulebase.classifiers if c.kind == Q)


def _row(c: Classifier) -> tuple[str, ...]:
    return (c.kind, c.condition, c.action, f"{c.strength:.6f}", f"{c.q:.6f}", f"{c.age:.6g}", f"{c.error:.6f}")


def greedy_path(rulebase: RuleBase, start: State, goal: State) -> list[Classifier]:
    """The Q-classifiers the greedy policy activates from ``start`` to ``goal``, in order."""
    if start.n != rulebase.blocks or goal.n != rulebase.blocks:
        raise WorldError(f"the rule base is for {rulebase.blocks} blocks; the task has {start.n}")
    classifiers = ClassifierList(rulebase.classifiers)
    policy = QPolicy(classifiers, rulebase.blocks)
    from csql_sim.messages import format_action_message, format_state_message

    goal_index = policy.world.state_index(goal)
    path: list[Classifier] = []
    state, seen = start, {start}
    while state != goal:
        action = policy.act(state, goal)
        message = format_state_message(state, goal_index)
        path.append(classifiers.q_for(message)[format_action_message(action, rulebase.blocks)])
        state = successor(state, action)
        if state in seen:
            raise CsqlError(f"the greedy policy loops at {state.notation()} on the way to {goal.notation()}")
        seen.add(state)
    return path


def figure6_table(rulebase: RuleBase, start: State | None = None, goal: State | None = None) -> str:
    """The Q-classifiers in Figure 6's table form.

    Columns: T, Condition, Action, Strength, Q-value, Age, PredErr. With ``start`` and
    ``goal``, just the greedy path's classifiers in order; otherwise every Q-classifier,
    sorted by goal code then condition.
    """
    if (start is None) != (goal is None):
        raise CsqlError("give both a start and a goal, or neither")
    if start is not None:
        rows = greedy_path(rulebase, start, goal)
    else:
        qs = [c for c in rulebase.classifiers if c.kind == Q]
        rows = sorted(qs, key=lambda c: (c.condition[-1:], c.condition, c.action))
    table = [HEADER, *(_row(c) for c in rows)]
    widths = [max(len(r[k]) for r in table) for k in range(len(HEADER))]
    return "\n".join("  ".join(cell.ljust(w) for cell, w in zip(r, widths, strict=True)).rstrip() for r in table)
