"""``show`` of a goal-form rule base: its Q-classifiers in list order, each with its coverage.

A generalized Q-classifier decides every (state, goal) pair for which it is the first of
the match set (:mod:`csql_sim.core.policies.default_hierarchy`); its *coverage* is how many pairs
that is, so the coverages of a base that decides every pair sum to the number of pairs.
"""

from __future__ import annotations

from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.policies.default_hierarchy import DefaultHierarchy
from csql_sim.core.policies.rollout import rollout
from csql_sim.core.state.world import State
from csql_sim.infra.errors import CsqlError


def coverage_rows(rulebase: RuleBase, start: State | None = None, goal: State | None = None) -> list[dict]:
    """``show`` of a goal-form rule base: each Q-classifier with its coverage (pairs it decides), in list order.

    With ``start`` and ``goal``, only the classifiers that act along the plan, in order.
    """
    hierarchy = DefaultHierarchy.from_rulebase(rulebase)
    coverage = hierarchy.coverage()
    chosen = list(range(len(hierarchy.classifiers)))
    if start is not None and goal is not None:
        plan = rollout(hierarchy, start, goal, world_model=hierarchy.world_model)
        if not plan.reached:
            raise CsqlError(f"the rule base does not reach {goal.notation()} from {start.notation()}: {plan.reason}")
        chosen, state = [], start
        for action in plan.actions:
            chosen.append(hierarchy.classifiers.index(hierarchy.match_set(state, goal)[0]))
            state = hierarchy.world_model.predict_state(state, action)
    return [{"position": k + 1, "kind": "Q", "condition": hierarchy.classifiers[k].condition,
             "action": hierarchy.classifiers[k].action, "coverage": coverage[k],
             "strength": hierarchy.classifiers[k].strength, "q": hierarchy.classifiers[k].q} for k in chosen]


def coverage_table(rows: list[dict]) -> str:
    """:func:`coverage_rows` as a text table (T, #, Condition, Action, Coverage, Strength, Q-value)."""
    head = ("T", "#", "Condition", "Action", "Coverage", "Strength", "Q-value")
    table = [head, *((r["kind"], str(r["position"]), r["condition"], r["action"], str(r["coverage"]),
                      f"{r['strength']:.6f}", f"{r['q']:.6f}") for r in rows)]
    widths = [max(len(r[k]) for r in table) for k in range(len(head))]
    return "\n".join("  ".join(cell.ljust(w) for cell, w in zip(r, widths, strict=True)).rstrip() for r in table)
