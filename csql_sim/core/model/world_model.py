"""The world model: what the R-classifiers say about actions (paper section 5).

A :class:`WorldModel` is built from any set of R-classifiers: the paper's 36 for n = 3,
the generator's for other n, a rule file, or rules induced from experience. It answers
the two questions every part of the tool asks of the domain:

* :meth:`WorldModel.legal_actions`: the action messages whose precondition rules match a
  state message (Figure 2, step 3);
* :meth:`WorldModel.predict`: the state message after an action, produced by writing the
  action's code into the action slot and applying the one add-delete rule it activates
  (section 5's worked example).

Both are memoized inside the model. When no rule reads or writes the goal field (``#``
there in every condition and output, as in the paper's rules; checked, not assumed) the
memo is keyed by the message without its goal, so all goals share it.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable

import numpy as np

from csql_sim.core.classifiers.classifier_list import PatternIndex
from csql_sim.core.classifiers.lifted_rule import LiftedRule, ground_rules
from csql_sim.core.classifiers.r_classifier import (
    WILDCARD,
    AddDeleteRule,
    PreconditionRule,
    RClassifier,
    r_classifiers,
    validate_r_classifier,
)
from csql_sim.core.model.transition_table import ILLEGAL, TransitionTable
from csql_sim.core.state.message import (
    action_messages,
    format_action_message,
    format_state_message,
    layout,
    parse_state_message,
)
from csql_sim.core.state.world import Action, BlocksWorld, State, check_n
from csql_sim.infra.errors import CsqlError


class WorldModelError(CsqlError):
    """The R-classifiers give no prediction (or several) for a message."""


class WorldModel:
    """Legal actions and next states of the n-block world, as the R-classifiers say.

    Args:
        rules: R-classifiers (other classifiers are ignored by type); each must fit the
            n-block message grammar (:func:`~csql_sim.core.classifiers.r_classifier.validate_r_classifier`).
        n: number of blocks the messages are laid out for.

    Raises:
        RuleError: for a rule that no n-block world can hold (a foreign letter, ``#`` in an
            action message, an output that puts a block on itself, ...).

    Attributes:
        n: number of blocks.
        preconditions: the precondition rules, in the order given.
        add_deletes: the add-delete rules, in the order given.

    """

    def __init__(self, rules: Iterable[RClassifier], n: int) -> None:
        self.n = check_n(n)
        rules = tuple(rules)
        self.preconditions = tuple(r for r in rules if isinstance(r, PreconditionRule))
        self.add_deletes = tuple(r for r in rules if isinstance(r, AddDeleteRule))
        for rule in (*self.preconditions, *self.add_deletes):
            validate_r_classifier(rule, n, owner="world model")
        lay = layout(n)
        self._width = lay.action_width
        self._goal_at = lay.goal_start
        self._pre = PatternIndex(self.preconditions)
        self._post = PatternIndex(self.add_deletes)
        goal_blind = all(set(r.condition[self._goal_at:]) == {WILDCARD} for r in rules) and all(
            set(r.output[self._goal_at:]) == {WILDCARD} for r in self.add_deletes)
        self._key_end = self._goal_at if goal_blind else None
        self._legal: dict[str, tuple[str, ...]] = {}
        self._next: dict[str, str] = {}
        self._steps: dict[str, list[str | None]] = {}
        self._action_messages = action_messages(n)

    @classmethod
    @functools.cache
    def for_blocks(cls, n: int) -> WorldModel:
        """The built-in domain knowledge: the paper's rules for n = 3, generated otherwise (shared per n)."""
        return cls(r_classifiers(n), n)

    @classmethod
    def from_lifted(cls, rules: Iterable[LiftedRule], n: int) -> WorldModel:
        """The world model of lifted R-classifiers (:mod:`~csql_sim.core.classifiers.lifted_rule`) at n blocks."""
        return cls(ground_rules(rules, n), n)

    @functools.cached_property
    def table(self) -> TransitionTable:
        """Every state message of the n-block world matched and predicted once, as index arrays.

        Raises:
            WorldModelError: when the rules predict a message that is not a state of the world.
        """
        world = BlocksWorld.of(self.n)
        end = layout(self.n).goal_start
        body = {format_state_message(s, 0)[:end]: i for i, s in enumerate(world.states)}
        code = {m: k for k, m in enumerate(self._action_messages)}
        table = np.full((len(world.states), len(world.actions)), ILLEGAL, np.int32)
        for s, state in enumerate(world.states):
            message = format_state_message(state, 0)
            for action in self.legal_actions(message):
                nxt = body.get(self.predict(message, action)[:end])
                if nxt is None:
                    raise WorldModelError(f"the rules predict no state of the world for {action} in {message}")
                table[s, code[action]] = nxt
        return TransitionTable(self.n, table)

    def legal_actions(self, message: str) -> tuple[str, ...]:
        """The action messages of the precondition rules that match a state message."""
        key = message[: self._key_end]
        actions = self._legal.get(key)
        if actions is None:
            actions = self._legal[key] = tuple(r.action for r in self._pre.match(message))
        return actions

    def predict(self, message: str, action: str) -> str:
        """The state message after ``action`` (an action message) in ``message``.

        Raises:
            WorldModelError: when no add-delete rule, or more than one, matches.
        """
        w = self._width
        posted = message[0] + action[1 : 1 + w] + message[1 + w :]
        end = self._key_end
        body = self._next.get(posted[:end])
        if body is None:
            rules = self._post.match(posted)
            if len(rules) != 1:
                raise WorldModelError(f"{len(rules)} add-delete rules match {posted!r}")
            body = self._next[posted[:end]] = rules[0].apply(posted)[:end]
        return body if end is None else body + message[end:]

    def step(self, message: str, action: int) -> str:
        """:meth:`predict` for an action given by its index in the stable action order (memoized)."""
        row = self._steps.get(message)
        if row is None:
            row = self._steps[message] = [None] * len(self._action_messages)
        nxt = row[action]
        if nxt is None:
            nxt = row[action] = self.predict(message, self._action_messages[action])
        return nxt

    def predict_state(self, state: State, action: Action, goal: int = 0) -> State:
        """The state after ``action`` in ``state`` (messages formed for goal index ``goal``)."""
        message = format_state_message(state, goal)
        return parse_state_message(self.predict(message, format_action_message(action, self.n)), self.n).state

    def is_legal(self, state: State, action: Action, goal: int = 0) -> bool:
        """Whether a precondition rule proposes ``action`` in ``state``."""
        return format_action_message(action, self.n) in self.legal_actions(format_state_message(state, goal))
