"""The greedy policy over a classifier list (:class:`QPolicy`), and the policy contract's name here.

:class:`Policy` is the contract every policy implements (:mod:`csql_sim.core.policies.contract`),
imported here too. :class:`QPolicy` is greedy over learned Q-classifiers;
:class:`~csql_sim.core.policies.greedy_table.GreedyTable` gives the same answers as a table, built
from a rule file's arrays. Rollouts and all-pairs checks of any policy are in
:mod:`csql_sim.core.policies.rollout`.
"""

from __future__ import annotations

from csql_sim.core.classifiers.classifier_list import ClassifierList
from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.policies.contract import Policy
from csql_sim.core.state.message import format_state_message, parse_action_message
from csql_sim.core.state.world import Action, BlocksWorld, State
from csql_sim.infra.errors import CsqlError

VALUES = ("q", "strength")

__all__ = ["VALUES", "NoRuleError", "Policy", "QPolicy"]


class NoRuleError(CsqlError):
    """A rule base has no Q-classifier for a state message."""


class QPolicy(Policy):
    """Greedy policy over Q-classifiers: the action of the highest value (ties: list order).

    Args:
        classifiers: a classifier list holding Q-classifiers (R-classifiers are ignored).
        n: number of blocks the messages describe.
        value: the field greedy selection follows: ``"q"`` (Q-learning) or
            ``"strength"`` (the bucket brigade's learned value).

    """

    name = "rules"

    def __init__(self, classifiers: ClassifierList, n: int, value: str = "q") -> None:
        if value not in VALUES:
            raise CsqlError(f"value must be one of {', '.join(VALUES)}, got {value!r}")
        self.classifiers = classifiers
        self.n = self.blocks = n
        self.value = value
        self.world = BlocksWorld.of(n)

    @classmethod
    def from_rulebase(cls, rulebase: RuleBase) -> QPolicy:
        """The greedy policy of a rule base (its ``meta["value"]`` names the field, default q)."""
        return cls(ClassifierList(rulebase.classifiers), rulebase.blocks, rulebase.meta.get("value", "q"))

    def act(self, state: State, goal: State) -> Action | None:
        """The greedy action; raises NoRuleError naming the state message if none matches."""
        if state == goal:
            return None
        message = format_state_message(state, self.world.state_index(goal))
        rules = self.classifiers.q_for(message).values()
        if not rules:
            raise NoRuleError(f"no Q-classifier matches state {message} ({state.notation()})")
        field = self.value
        best = max(rules, key=lambda c: getattr(c, field))  # max keeps the first of equal values
        return parse_action_message(best.action, self.n)
