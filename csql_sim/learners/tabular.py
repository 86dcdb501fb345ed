"""LT-QL: Q-learning with a look-up table over all states and all actions (section 6).

The table has one row per (state, goal) pair visited and one entry per action of the
world (18 for n=3): it is told the sizes beforehand and nothing about legality. Boltzmann
selection (eq. 3) runs over all actions; an illegal action leaves the state unchanged.
"""

from __future__ import annotations

import numpy as np

from csql_sim.classifiers import Classifier, Q
from csql_sim.learners.base import UNSEEN, Learner
from csql_sim.learners.params import TabularParams
from csql_sim.learners.selection import boltzmann
from csql_sim.messages import format_action_message, format_state_message, parse_state_message
from csql_sim.rulebase import RuleBase


class Row:
    """One table row: Q-hat(x, .) over all actions of a (state, goal) pair.

    Attributes:
        state: state index.
        goal: goal index.
        q: Q-hat per action index.
        error: |epsilon| per action at its last update.
        last: the step of each action's last update.
        born: the step the row was created.
        next: per action, the next row, ``None`` at the goal, or unseen.

    """

    __slots__ = ("state", "goal", "q", "error", "last", "born", "next")

    def __init__(self, state: int, goal: int, actions: int, q0: float, born: int) -> None:
        self.state = state
        self.goal = goal
        self.q = [q0] * actions
        self.error = [0.0] * actions
        self.last = [born] * actions
        self.born = born
        self.next: list = [UNSEEN] * actions


class TabularQ(Learner):
    """LT-QL: TD(0) Q-learning on a look-up table (eq. 1-3)."""

    method = "lt-ql"
    params: TabularParams

    def __init__(self, n: int, params: TabularParams, rng: np.random.Generator) -> None:
        super().__init__(n, params, rng)
        self._rows: dict[tuple[int, int], Row] = {}
        self._actions = len(self.world.actions)

    def node(self, state: int, goal: int) -> Row:
        """The table row of (state, goal), allocated on first use."""
        row = self._rows.get((state, goal))
        if row is None:
            row = Row(state, goal, self._actions, self.params.q0, self.t)
            self._rows[(state, goal)] = row
        return row

    def observe(self, message: str) -> Row:
        """The row of an observed state message."""
        parsed = parse_state_message(message, self.n)
        return self.node(self.world.state_index(parsed.state), parsed.goal)

    def action_index(self, node: Row, i: int) -> int:
        """Candidates are all actions: ``i`` itself."""
        return i

    def value(self, node: Row, i: int) -> float:
        """Q-hat of action ``i``."""
        return node.q[i]

    def select(self, node: Row, temperature: float, u: float) -> int:
        """Boltzmann over all actions (eq. 3)."""
        return boltzmann(node.q, temperature, u)

    def successor(self, node: Row, i: int) -> Row | None:
        """The environment's next row; an illegal action leaves the state unchanged."""
        nxt = node.next[i]
        if nxt is UNSEEN:
            s = self.world.next_state[node.state][i]
            if s < 0:
                s = node.state
            nxt = None if s == node.goal else self.node(s, node.goal)
            node.next[i] = nxt
        return nxt

    def update(self, node: Row, i: int, nxt: Row | None, t: int) -> None:
        """Eq. 1 and 2 on the table entry; records |epsilon| and the step."""
        p = self.params
        target = p.payoff if nxt is None else p.gamma * max(nxt.q)
        eps = target - node.q[i]
        node.q[i] += p.eta * eps
        node.error[i] = eps if eps >= 0.0 else -eps
        node.last[i] = t

    def rulebase(self, meta: dict | None = None) -> RuleBase:
        """The table as Q-classifiers (every action of every visited row).

        No R-classifiers: LT-QL has no domain knowledge. Strength is 1 - |epsilon| with
        the same per-step growth as CS-QL.
        """
        p = self.params
        world = self.world
        actions = [format_action_message(a, self.n) for a in world.actions]
        out: list[Classifier] = []
        for (s, g), row in sorted(self._rows.items(), key=lambda kv: (kv[0][1], kv[0][0])):
            message = format_state_message(world.states[s], g)
            for a, action in enumerate(actions):
                err = row.error[a] + p.error_increment * (self.t - row.last[a])
                out.append(
                    Classifier(
                        Q, message, action, q=row.q[a], strength=1.0 - err,
                        age=(self.t - row.born) / p.age_unit, error=err, last_active=self.t,
                    )
                )
        return RuleBase(blocks=self.n, classifiers=out, meta=dict(meta or {}))
