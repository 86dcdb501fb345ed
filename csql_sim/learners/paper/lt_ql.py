"""LT-QL: Q-learning with a look-up table over all states and all actions (section 6).

The table has one row per (state, goal) pair visited and one entry per action of the
world (18 for n=3): it is told the sizes beforehand and nothing about legality. Boltzmann
selection (eq. 3) runs over all actions; an illegal action leaves the state unchanged.
"""

from __future__ import annotations

import numpy as np

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.core.state.message import format_action_message, format_state_message, parse_state_message
from csql_sim.core.state.world import BlocksWorld
from csql_sim.learners.paper.learner import Transition
from csql_sim.learners.paper.params import TabularParams
from csql_sim.learners.paper.selection import boltzmann
from csql_sim.learners.paper.trial import StepLearner


class Row:
    """One table row: Q-hat(x, .) over all actions of a (state, goal) pair.

    Attributes:
        state: state index.
        goal: goal index.
        q: Q-hat per action index.
        error: |epsilon| per action at its last update.
        last: the step of each action's last update.
        born: the step the row was created.

    """

    __slots__ = ("state", "goal", "q", "error", "last", "born")

    def __init__(self, state: int, goal: int, actions: int, q0: float, born: int) -> None:
        self.state = state
        self.goal = goal
        self.q = [q0] * actions
        self.error = [0.0] * actions
        self.last = [born] * actions
        self.born = born


class TableModel:
    """The true transitions of the n-block world on messages: LT-QL's environment.

    An illegal action leaves the state unchanged, as LT-QL assumes. Memoized per message.
    """

    def __init__(self, world: BlocksWorld) -> None:
        self.world = world
        self._next: dict[str, list[str | None]] = {}

    def step(self, message: str, action: int) -> str:
        """The state message after action index ``action``."""
        row = self._next.get(message)
        if row is None:
            row = self._next[message] = [None] * len(self.world.actions)
        nxt = row[action]
        if nxt is None:
            parsed = parse_state_message(message, self.world.n)
            s = self.world.state_index(parsed.state)
            after = self.world.next_state[s][action]
            nxt = row[action] = format_state_message(self.world.states[after if after >= 0 else s], parsed.goal)
        return nxt


class TabularQ(StepLearner):
    """LT-QL: TD(0) Q-learning on a look-up table (eq. 1-3)."""

    method = "lt-ql"
    params: TabularParams

    def __init__(self, n: int, params: TabularParams, rng: np.random.Generator) -> None:
        super().__init__(n, params, rng)
        self._rows: dict[str, Row] = {}
        self._actions = len(self.world.actions)
        self._model = TableModel(self.world)

    @property
    def model(self) -> TableModel:
        """Trials run on the true transition table."""
        return self._model

    def row(self, message: str) -> Row:
        """The table row of a state message, allocated on first use."""
        row = self._rows.get(message)
        if row is None:
            parsed = parse_state_message(message, self.n)
            row = Row(self.world.state_index(parsed.state), parsed.goal, self._actions, self.params.q0, self.t)
            self._rows[message] = row
        return row

    def act(self, observation: str, temperature: float) -> int:
        """Boltzmann over all actions (eq. 3)."""
        return boltzmann(self.row(observation).q, temperature, self.uniforms.next())

    def value(self, observation: str, action: int) -> float:
        """Q-hat of ``action``."""
        return self.row(observation).q[action]

    def learn(self, transition: Transition) -> None:
        """Eq. 1 and 2 on the table entry; records |epsilon| and the step."""
        row = self.row(transition.observation)
        nxt = None if transition.terminated else self.row(transition.next_observation)
        self.t += 1
        p = self.params
        a = transition.action
        target = p.payoff if nxt is None else p.gamma * max(nxt.q)
        eps = target - row.q[a]
        row.q[a] += p.eta * eps
        row.error[a] = eps if eps >= 0.0 else -eps
        row.last[a] = self.t

    def greedy_table(self) -> GreedyTable:
        """The greedy action of every visited row, straight from the table (its rule base is large)."""
        count = len(self.world.states)
        best = np.full(count * count, -1, np.int8)
        for row in self._rows.values():
            best[row.state * count + row.goal] = row.q.index(max(row.q))
        return GreedyTable(self.n, best)

    def counts(self) -> tuple[int, int]:
        """No R-classifiers; one Q-classifier per action of every visited row."""
        return 0, len(self._rows) * self._actions

    def rulebase(self, meta: dict | None = None) -> RuleBase:
        """The table as Q-classifiers (every action of every visited row).

        No R-classifiers: LT-QL has no domain knowledge. Strength is 1 - |epsilon| with
        the same per-step growth as CS-QL.
        """
        p = self.params
        world = self.world
        actions = [format_action_message(a, self.n) for a in world.actions]
        out: list[QClassifier] = []
        for row in sorted(self._rows.values(), key=lambda r: (r.goal, r.state)):
            message = format_state_message(world.states[row.state], row.goal)
            for a, action in enumerate(actions):
                err = row.error[a] + p.error_increment * (self.t - row.last[a])
                out.append(
                    QClassifier(
                        message, action, q=row.q[a], strength=1.0 - err,
                        age=(self.t - row.born) / p.age_unit, error=err, last_active=self.t, born=row.born,
                    )
                )
        return RuleBase(blocks=self.n, classifiers=out, meta=dict(meta or {}))
