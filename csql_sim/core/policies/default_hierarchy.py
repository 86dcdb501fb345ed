"""Generalized Q-classifiers as a default hierarchy: the match set, then the first in list order.

A rule base in the goal form (:mod:`csql_sim.core.state.goal_message`) holds Q-classifiers whose
conditions have ``#`` and so match many (state, goal) pairs. It plans as the processing
block does (Figure 2, steps 3-5):

1. the state's goal-form message is posted;
2. the precondition R-classifiers (the world model) name the candidate actions;
3. the **match set** is every Q-classifier whose condition accepts the message and whose
   action is a candidate, in list order;
4. **action selection**: the first classifier of the match set acts (an ordered default
   hierarchy, Holland and Riolo: specific exceptions are listed before the general
   defaults they override).

:meth:`DefaultHierarchy.act` does exactly this for one state; :meth:`DefaultHierarchy.decisions`
computes the same answers for every pair at once with numpy (the same rule, vectorized;
tested to agree), which :func:`csql_sim.core.policies.loader.load_policy` wraps as a
:class:`~csql_sim.core.policies.greedy_table.GreedyTable` so that every command reads it as any rule
base. Nothing is planned: no distance, table of answers or search is consulted.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import WILDCARD, matches
from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.policies.contract import Policy
from csql_sim.core.policies.policy import NoRuleError
from csql_sim.core.state.goal_message import GoalForm, form_of, format_goal_message, pattern_problem
from csql_sim.core.state.goal_message_index import pair_messages
from csql_sim.core.state.message import action_messages, format_state_message, parse_action_message
from csql_sim.core.state.world import Action, BlocksWorld, State
from csql_sim.infra.errors import CsqlError


@dataclass(frozen=True)
class Decisions:
    """The default hierarchy's answer for every (state, goal) pair.

    Attributes:
        best: ``int8 [states * states]``, the action index chosen (-1: empty match set or the goal).
        rule: ``int32 [states * states]``, the position of the deciding Q-classifier (-1: none).
    """

    best: np.ndarray
    rule: np.ndarray


class DefaultHierarchy(Policy):
    """The Policy interface over ordered goal-form Q-classifiers.

    Args:
        form: the goal form the conditions are written in.
        classifiers: the Q-classifiers, in list order (earlier ones take precedence).
        world_model: the R-classifiers naming the candidate actions (default: the built-in ones).
    """

    name = "rules"

    def __init__(self, form: GoalForm, classifiers: list[QClassifier], world_model: WorldModel | None = None) -> None:
        self.form = form
        self.n = self.blocks = form.n
        self.classifiers = list(classifiers)
        self.world_model = world_model or WorldModel.for_blocks(form.n)
        self.world = BlocksWorld.of(form.n)
        for k, c in enumerate(self.classifiers, start=1):
            problem = pattern_problem(c.condition, form)
            if problem:
                raise CsqlError(f"Q-classifier {k}: {problem}")

    @classmethod
    def from_rulebase(cls, rulebase: RuleBase) -> DefaultHierarchy:
        """The default hierarchy of a goal-form rule base (its R-classifiers, if any, are the world model)."""
        form = form_of(rulebase.meta, rulebase.blocks)
        if form is None:
            raise CsqlError("the rule base is in the index form (one Q-classifier per state and goal), "
                            "not the goal form")
        qs = [c for c in rulebase.classifiers if isinstance(c, QClassifier)]
        rs = [c for c in rulebase.classifiers if not isinstance(c, QClassifier)]
        return cls(form, qs, WorldModel(rs, rulebase.blocks) if rs else None)

    def match_set(self, state: State, goal: State) -> list[QClassifier]:
        """The Q-classifiers that accept the pair's goal-form message and propose a candidate action."""
        message = format_goal_message(state, goal, self.form)
        candidates = set(self.world_model.legal_actions(format_state_message(state, self.world.state_index(goal))))
        return [c for c in self.classifiers if c.action in candidates and matches(c.condition, message)]

    def act(self, state: State, goal: State) -> Action | None:
        """The first classifier of the match set's action; None at the goal; NoRuleError if the set is empty."""
        if state == goal:
            return None
        found = self.match_set(state, goal)
        if not found:
            raise NoRuleError(f"no Q-classifier matches {format_goal_message(state, goal, self.form)} "
                              f"({state.notation()} -> {goal.notation()})")
        return parse_action_message(found[0].action, self.n)

    @functools.cached_property
    def _action_of(self) -> list[int]:
        index = {m: i for i, m in enumerate(action_messages(self.n))}
        return [index[c.action] for c in self.classifiers]

    def decisions(self) -> Decisions:
        """:meth:`act` for every pair at once (n <= 5): the chosen action and the deciding classifier."""
        messages = pair_messages(self.form)
        count = len(self.world.states)
        legal = self.world_model.table.next_state >= 0
        state_of = np.repeat(np.arange(count), count)
        best = np.full(count * count, -1, np.int8)
        rule = np.full(count * count, -1, np.int32)
        open_ = np.ones(count * count, bool)
        open_[np.arange(count) * (count + 1)] = False  # the goal itself: no action
        for k, (c, a) in enumerate(zip(self.classifiers, self._action_of, strict=True)):
            hit = open_ & legal[state_of, a]
            for pos, ch in enumerate(c.condition):
                if ch != WILDCARD:
                    hit &= messages[:, pos] == ord(ch)
            best[hit], rule[hit] = a, k
            open_ &= ~hit
        return Decisions(best, rule)

    def coverage(self) -> list[int]:
        """How many (state, goal) pairs each classifier decides (is the first of the match set for)."""
        rule = self.decisions().rule
        return np.bincount(rule[rule >= 0], minlength=len(self.classifiers)).tolist()
