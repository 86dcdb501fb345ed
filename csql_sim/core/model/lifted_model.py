"""The world model of lifted R-classifiers on relational states, for any n <= 26.

For n <= 6 the lifted rules can be grounded into message strings
(:meth:`csql_sim.core.model.world_model.WorldModel.from_lifted`). Past six blocks there is no
ground rule set to write out, so :class:`LiftedWorldModel` interprets the lifted rules
directly on a :class:`~csql_sim.core.state.state.State`: an action is legal when the
precondition rule of its operator holds under the binding of its blocks, and its next
state is what the operator's add-delete rule writes. Nothing else is assumed: the
legal actions and successors are the rules' own.
"""

from __future__ import annotations

from collections.abc import Iterable

from csql_sim.core.classifiers.lifted_rule import (
    POST,
    PRE,
    LiftedRule,
    LiftedRuleError,
    X,
    Y,
    apply_output,
    bindings,
    bound_action,
    field_holds,
)
from csql_sim.core.state.world import HAND, Action, ActionKind, State, WorldError


class _ClearView:
    """``clear[i]`` of a state, computed for the blocks asked about only."""

    def __init__(self, state: State) -> None:
        self.state = state

    def __getitem__(self, i: int) -> bool:
        support = self.state.support
        return support[i] != HAND and i not in support  # a scan in C: no table of the blocks above


class LiftedWorldModel:
    """Legal actions and next states of relational states, as lifted R-classifiers say.

    Args:
        rules: lifted rules; at most one precondition rule and one add-delete rule per operator.

    Raises:
        LiftedRuleError: when an operator has two rules of one kind.
    """

    def __init__(self, rules: Iterable[LiftedRule]) -> None:
        self.rules = tuple(rules)
        self.pre: dict[ActionKind, LiftedRule] = {}
        self.post: dict[ActionKind, LiftedRule] = {}
        for rule in self.rules:
            table = self.pre if rule.kind == PRE else self.post
            if rule.operator in table:
                kind = "precondition" if rule.kind == PRE else POST
                raise LiftedRuleError(f"two {kind} rules for {rule.operator.value}")
            table[rule.operator] = rule

    @staticmethod
    def _binding(action: Action) -> dict[str, int]:
        return {X: action.block} if action.target is None else {X: action.block, Y: action.target}

    def is_legal(self, state: State, action: Action) -> bool:
        """Whether the precondition rule of the action's operator matches under its binding."""
        rule = self.pre.get(action.kind)
        if rule is None:
            return False
        clear, held = _ClearView(state), state.held  # the bound blocks' flags alone: O(1) at any n
        binding = self._binding(action)
        return all(field_holds(f, state.support, clear, held, binding) for f in rule.fields)

    def legal_actions(self, state: State) -> tuple[Action, ...]:
        """The actions whose precondition rules match, in the stable action order."""
        clear, held = state.clear(), state.held
        out = []
        for kind in (ActionKind.UNSTACK, ActionKind.PICKUP, ActionKind.PUTDOWN, ActionKind.STACK):
            rule = self.pre.get(kind)
            if rule is None:
                continue
            for binding in bindings(kind, state.n):
                if all(field_holds(f, state.support, clear, held, binding) for f in rule.fields):
                    out.append(bound_action(kind, binding))
        return tuple(out)

    def successor(self, state: State, action: Action) -> State:
        """The state the add-delete rule of the action's operator writes.

        Raises:
            WorldError: when the action is not legal, or the rules give no valid next state.
        """
        rule = self.post.get(action.kind)
        if rule is None or not self.is_legal(state, action):
            raise WorldError(f"the lifted rules give no next state for {action.kind.value} here")
        binding = self._binding(action)
        support = apply_output(rule, state.support, binding)
        written = {binding[f.var] for f in rule.fields if f.what == "on"}  # the output writes these blocks alone
        changed = tuple(sorted(i for i in written if state.support[i] != support[i]))
        return state.with_changes(support, changed)  # the names ride along
