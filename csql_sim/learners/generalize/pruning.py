"""Pruning and Figure 6's table form."""

from __future__ import annotations

import numbers

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.policies.policy import QPolicy
from csql_sim.core.policies.rollout import rollout
from csql_sim.core.state.message import format_action_message, format_state_message
from csql_sim.core.state.notation import parse_state_arg
from csql_sim.core.state.world import State, WorldError
from csql_sim.infra.errors import CsqlError

HEADER = ("T", "Condition", "Action", "Strength", "Q-value", "Age", "PredErr")


def prune(rulebase: RuleBase, threshold: float = 0.1) -> RuleBase:
    """A copy of ``rulebase`` without the Q-classifiers whose strength is below ``threshold``.

    R-classifiers are always kept.

    Raises:
        CsqlError: unless ``threshold`` is a number in [0, 1] (as ``prune --threshold``; NaN is refused).
    """
    if isinstance(threshold, bool) or not isinstance(threshold, numbers.Real) or not 0.0 <= threshold <= 1.0:
        raise CsqlError(f"threshold must be a number in [0, 1], got {threshold!r}")
    threshold = float(threshold)  # meta holds a plain float (a numpy scalar could not be written)
    kept = [c for c in rulebase.classifiers if not isinstance(c, QClassifier) or c.strength >= threshold]
    meta = dict(rulebase.meta)
    meta["pruned_at"] = threshold
    return RuleBase(blocks=rulebase.blocks, classifiers=kept, meta=meta)


def count_q(rulebase: RuleBase) -> int:
    """Number of Q-classifiers in a rule base."""
    return sum(1 for c in rulebase.classifiers if isinstance(c, QClassifier))


def _row(c: QClassifier) -> tuple[str, ...]:
    return (c.kind, c.condition, c.action, f"{c.strength:.6f}", f"{c.q:.6f}", f"{c.age:.6g}", f"{c.error:.6f}")


def greedy_path(rulebase: RuleBase, start: State | str, goal: State | str) -> list[QClassifier]:
    """The Q-classifiers the greedy policy activates from ``start`` to ``goal``, in order.

    ``start`` and ``goal`` are states or notation strings (``"CBA"``, a state message).
    The path is predicted by the rule base's own R-classifiers when it has them, by the
    built-in ones otherwise.
    """
    start, goal = _state(start, rulebase.blocks), _state(goal, rulebase.blocks)
    if start.n != rulebase.blocks or goal.n != rulebase.blocks:
        raise WorldError(f"the rule base is for {rulebase.blocks} blocks; the task has {start.n}")
    policy = QPolicy.from_rulebase(rulebase)
    rules = policy.classifiers.r_classifiers
    model = WorldModel(rules, rulebase.blocks) if rules else WorldModel.for_blocks(rulebase.blocks)
    plan = rollout(policy, start, goal, world_model=model)
    if not plan.reached:
        raise CsqlError(f"the greedy policy does not reach {goal.notation()} from {start.notation()}: {plan.reason}")
    goal_index = policy.world.state_index(goal)
    path: list[QClassifier] = []
    state = start
    for action in plan.actions:
        message = format_state_message(state, goal_index)
        path.append(policy.classifiers.q_for(message)[format_action_message(action, rulebase.blocks)])
        state = model.predict_state(state, action, goal_index)
    return path


def _state(value: State | str, n: int) -> State:
    return value if isinstance(value, State) else parse_state_arg(value, n)


def figure6_classifiers(rulebase: RuleBase, start: State | str | None = None,
                        goal: State | str | None = None) -> list[QClassifier]:
    """The Q-classifiers of Figure 6: the greedy path of a task, or all of them by goal then condition."""
    if (start is None) != (goal is None):
        raise CsqlError("give both a start and a goal, or neither")
    if start is not None:
        return greedy_path(rulebase, start, goal)
    qs = [c for c in rulebase.classifiers if isinstance(c, QClassifier)]
    return sorted(qs, key=lambda c: (c.condition[-1:], c.condition, c.action))


def figure6_rows(rulebase: RuleBase, start: State | str | None = None, goal: State | str | None = None) -> list[dict]:
    """:func:`figure6_classifiers` as JSON objects (kind, condition, action, strength, q, age, error)."""
    return [{"kind": c.kind, "condition": c.condition, "action": c.action, "strength": c.strength, "q": c.q,
             "age": c.age, "error": c.error} for c in figure6_classifiers(rulebase, start, goal)]


def figure6_table(rulebase: RuleBase, start: State | str | None = None, goal: State | str | None = None) -> str:
    """The Q-classifiers in Figure 6's table form.

    Columns: T, Condition, Action, Strength, Q-value, Age, PredErr. With ``start`` and
    ``goal`` (States, or notation strings such as ``"CBA"`` as ``env.reset`` accepts, or
    state messages), just the greedy path's classifiers in order; otherwise every
    Q-classifier, sorted by goal code then condition.
    """
    rows = figure6_classifiers(rulebase, start, goal)
    table = [HEADER, *(_row(c) for c in rows)]
    widths = [max(len(r[k]) for r in table) for k in range(len(HEADER))]
    return "\n".join("  ".join(cell.ljust(w) for cell, w in zip(r, widths, strict=True)).rstrip() for r in table)
