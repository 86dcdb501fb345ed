"""CS-QL: Q-learning through the classifier system (paper section 4, Figure 2).

One step of :meth:`Learner.run_trial` with a :class:`ClassifierSystemLearner` is the
paper's interaction cycle:

1. *post* the state message (:meth:`ClassifierSystemLearner.node`);
2. *match* the precondition R-classifiers to get the candidate actions (step 3);
3. *cover*: make sure a Q-classifier exists for each (state, action) pair (step 4);
4. *select* an action by eq. 3 over the candidates' Q-values (step 5);
5. *predict* the next state message with the add-delete R-classifiers (the world model);
6. *update* the classifier that proposed the action with eq. 1, 2 and 4 (step 6).

The processing block (Figure 1) retrieves classifiers through the :class:`ClassifierList`
index, never by scanning the list. It memoizes its retrievals per message in a
:class:`Node` (the candidates' Q-classifiers and, once predicted, the successor node of
each), because the retrieval for a message never changes while nothing is removed:
the same classifier objects are found, and the same add-delete rule fires. The
R-classifiers have ``#`` in the goal field (checked when the learner is built), so their
match and prediction results are memoized per message body, shared by all goals.
"""

from __future__ import annotations

import numpy as np

from csql_sim.classifiers import Classifier, ClassifierList, Q
from csql_sim.learners.base import UNSEEN, Learner
from csql_sim.learners.params import CommonParams, CSQLParams
from csql_sim.learners.selection import boltzmann
from csql_sim.messages import decode_code, format_state_message, layout
from csql_sim.rulebase import RuleBase
from csql_sim.rules import domain_knowledge

INF = float("inf")


class Node:
    """The processing block's memo for one state message.

    Attributes:
        message: the state message (action slot ``0``).
        goal: the goal index (also the message's goal code).
        qs: the candidates' Q-classifiers, in precondition-rule order.
        next: per candidate, the successor node, ``None`` at the goal, or unseen.

    """

    __slots__ = ("message", "goal", "qs", "next")

    def __init__(self, message: str, goal: int, qs: tuple[Classifier, ...]) -> None:
        self.message = message
        self.goal = goal
        self.qs = qs
        self.next: list = [UNSEEN] * len(qs)


class ClassifierSystemLearner(Learner):
    """The classifier-system part shared by CS-QL and the bucket-brigade learners.

    Attributes:
        classifiers: the classifier list (R-classifiers from :func:`domain_knowledge`,
            Q-classifiers created by :meth:`cover`).

    """

    def __init__(self, n: int, params: CommonParams, rng: np.random.Generator) -> None:
        super().__init__(n, params, rng)
        self.classifiers: ClassifierList = domain_knowledge(n)
        self._nodes: dict[str, Node] = {}
        self._born: dict[int, int] = {}
        lay = layout(n)
        self._width = lay.action_width
        self._goal_at = lay.goal_start
        # The R-classifiers neither read nor write the goal field ('#' there in every
        # condition and add-delete output), so match and predict results depend on the
        # rest of the message only: memoize them per message body. Checked, not assumed.
        self._goal_blind = all(
            set(c.condition[self._goal_at :]) == {"#"}
            and (c.action[0] != "S" or set(c.action[self._goal_at :]) == {"#"})
            for c in self.classifiers.of_kind("R")
        )
        self._matched: dict[str, list[str]] = {}
        self._predicted: dict[str, str] = {}
        states = self.world.states
        self._goal_messages = [format_state_message(s, g) for g, s in enumerate(states)]
        self._posted: dict[tuple[int, int], Node] = {}

    # -- Figure 2, steps 1-4 -----------------------------------------------------------
    def node(self, state: int, goal: int) -> Node:
        """Post the state message of ``state`` for ``goal`` and process it (steps 1-4)."""
        node = self._posted.get((state, goal))
        if node is None:
            message = format_state_message(self.world.states[state], goal)
            node = self._posted[(state, goal)] = self.process(message, goal)
        return node

    def observe(self, message: str) -> Node:
        """Process an observed state message (its goal code names the goal)."""
        return self.process(message, decode_code(message[self._goal_at :]))

    def action_index(self, node: Node, i: int) -> int:
        """The world's action index of candidate ``i`` (its action code minus one)."""
        return decode_code(node.qs[i].action[1 : 1 + self._width]) - 1

    def process(self, message: str, goal: int) -> Node:
        """The processing block for one state message: match, then cover (memoized)."""
        node = self._nodes.get(message)
        if node is None:
            node = Node(message, goal, self.cover(message, self.match(message)))
            self._nodes[message] = node
        return node

    def match(self, message: str) -> list[str]:
        """Step 3: the candidate action messages of the satisfied precondition rules."""
        key = message[: self._goal_at] if self._goal_blind else message
        actions = self._matched.get(key)
        if actions is None:
            actions = self._matched[key] = [c.action for c in self.classifiers.preconditions(message)]
        return actions

    def cover(self, message: str, actions: list[str]) -> tuple[Classifier, ...]:
        """Step 4: a Q-classifier for each (state, action) pair, creating missing ones."""
        before = len(self.classifiers.q_for(message))
        found = self.classifiers.cover(message, actions, **self.new_fields())
        if len(found) != before:
            for c in found.values():
                self._born.setdefault(id(c), self.t)
        return tuple(found[a] for a in actions)

    def new_fields(self) -> dict:
        """Field values of a freshly created Q-classifier."""
        return {"q": self.params.q0, "strength": 1.0, "error": 0.0, "last_active": self.t}

    # -- world model -------------------------------------------------------------------
    def predict(self, message: str, action: str) -> str:
        """The next state message, predicted by the world model.

        The action code is written into the action slot and the add-delete R-classifier
        it activates rewrites the message (section 5's worked example).
        """
        w = self._width
        posted = message[0] + action[1 : 1 + w] + message[1 + w :]
        if not self._goal_blind:
            return self.classifiers.predict(posted)
        key = posted[: self._goal_at]
        body = self._predicted.get(key)
        if body is None:
            body = self._predicted[key] = self.classifiers.predict(posted)[: self._goal_at]
        return body + message[self._goal_at :]

    def successor(self, node: Node, i: int) -> Node | None:
        """The predicted successor node of candidate ``i`` (``None`` at the goal)."""
        nxt = node.next[i]
        if nxt is UNSEEN:
            message = self.predict(node.message, node.qs[i].action)
            nxt = None if message == self._goal_messages[node.goal] else self.process(message, node.goal)
            node.next[i] = nxt
        return nxt

    # -- export --------------------------------------------------------------------------
    def settle(self) -> None:
        """Bring every Q-classifier's derived fields (age, error, strength) up to now."""
        unit = self.params.age_unit
        for c in self.classifiers:
            if c.kind == Q:
                c.age = (self.t - self._born.get(id(c), self.t)) / unit

    def rulebase(self, meta: dict | None = None) -> RuleBase:
        """The whole classifier list (R and Q), settled to the current step."""
        self.settle()
        return RuleBase(blocks=self.n, classifiers=list(self.classifiers), meta=dict(meta or {}))


class CSQL(ClassifierSystemLearner):
    """Classifier-system Q-learning (section 4) with eq. 1-4."""

    method = "cs-ql"
    params: CSQLParams

    def __init__(self, n: int, params: CSQLParams, rng: np.random.Generator) -> None:
        super().__init__(n, params, rng)
        self._gamma, self._eta, self._payoff = params.gamma, params.eta, params.payoff

    def value(self, node: Node, i: int) -> float:
        """The Q-value of candidate ``i``."""
        return node.qs[i].q

    def select(self, node: Node, temperature: float, u: float) -> int:
        """Step 5: Boltzmann selection over the candidates' Q-values (eq. 3).

        A lone candidate (6 of the 22 states for n=3 have one legal action) is chosen
        without evaluating eq. 3; the uniform is consumed either way, so results are
        identical.
        """
        qs = node.qs
        if len(qs) == 1:
            return 0
        return boltzmann([c.q for c in qs], temperature, u)

    def update(self, node: Node, i: int, nxt: Node | None, t: int) -> None:
        """Step 6: eq. 2's epsilon, eq. 1's Q update; |epsilon| reset, last_active = t.

        The growth of |epsilon| by ``error_increment`` per step is applied lazily from
        ``last_active`` (see :meth:`error`), so an update touches one classifier only.
        """
        c = node.qs[i]
        if nxt is None:
            target = self._payoff
        else:
            best = -INF
            for d in nxt.qs:
                if d.q > best:
                    best = d.q
            target = self._gamma * best
        eps = target - c.q
        c.q += self._eta * eps
        c.error = eps if eps >= 0.0 else -eps
        c.last_active = t

    def error(self, c: Classifier) -> float:
        """|epsilon| now: the last prediction error plus the growth since (section 4)."""
        return c.error + self.params.error_increment * (self.t - c.last_active)

    def strength(self, c: Classifier) -> float:
        """Eq. 4: strength = 1 - |epsilon|."""
        return 1.0 - self.error(c)

    def settle(self) -> None:
        """Fold the lazy |epsilon| growth into ``error`` and set strength (eq. 4) and age."""
        super().settle()
        for c in self.classifiers:
            if c.kind == Q:
                c.error = self.error(c)
                c.strength = 1.0 - c.error
                c.last_active = self.t

    def sweep(self) -> int:
        """Greedy planning passes over every (start, goal) pair on the world model.

        Each pass predicts every pair's greedy path with the add-delete R-classifiers and
        updates its classifiers with eq. 1-2, so each becomes active. Passes repeat until
        no update in a pass has |epsilon| above ``sweep_tolerance`` (at most
        ``sweep_passes``). Returns the steps taken.
        """
        p = self.params
        before = self.t
        count = len(self.world.states)
        for _ in range(p.sweep_passes):
            start_t = self.t
            for goal in range(count):
                for start in range(count):
                    if start != goal:
                        self.run_trial(start, goal, 0.0, cap=count)
            worst = max(
                (c.error for c in self.classifiers if c.kind == Q and c.last_active >= start_t), default=0.0
            )
            if worst <= p.sweep_tolerance:
                break
        return self.t - before
