"""CS-QL: Q-learning through the classifier system (paper section 4, Figure 2).

One step of a trial with a :class:`ClassifierSystemLearner` is the paper's interaction
cycle:

1. *post* the state message to the processing block (:meth:`act`);
2. *match* the precondition R-classifiers to get the candidate actions (step 3);
3. *cover*: make sure a Q-classifier exists for each (state, action) pair (step 4);
4. *select* an action by eq. 3 over the candidates' Q-values (step 5);
5. *predict* the next state message with the world model (the add-delete R-classifiers);
6. *update* the classifier that proposed the action with eq. 1, 2 and 4 (step 6, :meth:`learn`).

Steps 1-3 live in :mod:`csql_sim.core.model.processing_block`, step 5 in :mod:`csql_sim.core.model.world_model`.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from csql_sim.core.classifiers.classifier_list import ClassifierList
from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import RClassifier, r_classifiers
from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.model.processing_block import MatchSet, ProcessingBlock
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.state.message import decode_code, layout, parse_state_message
from csql_sim.learners.paper.learner import Transition
from csql_sim.learners.paper.params import CommonParams, CSQLParams
from csql_sim.learners.paper.replay import Experience, SlotLayout, replay_reference
from csql_sim.learners.paper.selection import boltzmann
from csql_sim.learners.paper.trial import StepLearner, run_trial

INF = float("inf")


class ClassifierSystemLearner(StepLearner):
    """The classifier-system part shared by CS-QL and the bucket-brigade learners.

    Args:
        n: number of blocks.
        params: the learner's parameters.
        rng: the only source of randomness.
        rules: the R-classifiers (default: the built-in domain knowledge for n blocks).

    Attributes:
        classifiers: the classifier list (the R-classifiers, then Q-classifiers as covered).
        world_model: the R-classifiers' world model.
        block: the processing block that posts messages to the list.

    """

    def __init__(self, n: int, params: CommonParams, rng: np.random.Generator,
                 rules: tuple[RClassifier, ...] | None = None) -> None:
        super().__init__(n, params, rng)
        rules = r_classifiers(n) if rules is None else rules
        self.classifiers = ClassifierList(rules)
        self.world_model = WorldModel(rules, n)
        self.block = ProcessingBlock(self.classifiers, self.world_model, self.new_fields)
        self._chosen: tuple[MatchSet, int] | None = None

    @property
    def model(self) -> WorldModel:
        """Trials run on the world model (the add-delete R-classifiers)."""
        return self.world_model

    def new_fields(self) -> dict:
        """Field values of a freshly created Q-classifier."""
        return {"q": self.params.q0, "strength": 1.0, "error": 0.0, "last_active": self.t, "born": self.t}

    # -- act and learn -----------------------------------------------------------------
    def act(self, observation: str, temperature: float) -> int:
        """Post the message, select a candidate (eq. 3); returns its action index."""
        match_set = self.block.post(observation)
        i = self.select(match_set, temperature, self.uniforms.next())
        self._chosen = (match_set, i)
        return match_set.actions[i]

    def value(self, observation: str, action: int) -> float:
        """The chosen classifier's value (Q-value; strength for the bucket brigade)."""
        match_set = self.block.post(observation)
        return self.candidate_value(match_set.candidates[match_set.index_of(action)])

    def learn(self, transition: Transition) -> None:
        """Post the next message (covering it), tick the clock, update the chosen classifier."""
        chosen = self._chosen
        if chosen is None or chosen[0].message != transition.observation \
                or chosen[0].actions[chosen[1]] != transition.action:
            match_set = self.block.post(transition.observation)
            chosen = (match_set, match_set.index_of(transition.action))
        nxt = None if transition.terminated else self.block.post(transition.next_observation)
        self.t += 1
        self.update(chosen[0], chosen[1], nxt, self.t)
        self._chosen = None

    # -- what each method supplies -----------------------------------------------------
    def candidate_value(self, c: QClassifier) -> float:
        """A candidate's value for selection and the test task's mean."""
        return c.q

    def select(self, match_set: MatchSet, temperature: float, u: float) -> int:
        """Step 5: choose a candidate with uniform ``u``."""
        raise NotImplementedError

    def update(self, match_set: MatchSet, i: int, nxt: MatchSet | None, t: int) -> None:
        """Step 6: credit candidate ``i`` (``nxt`` is None at the goal) at step ``t``."""
        raise NotImplementedError

    # -- export --------------------------------------------------------------------------
    def settle(self) -> None:
        """Bring every Q-classifier's age up to now."""
        unit = self.params.age_unit
        for c in self.classifiers.q_classifiers:
            c.age = (self.t - c.born) / unit

    def rulebase(self, meta: dict | None = None) -> RuleBase:
        """The whole classifier list (R and Q), settled to the current step."""
        self.settle()
        return RuleBase(blocks=self.n, classifiers=list(self.classifiers), meta=dict(meta or {}))

    def counts(self) -> tuple[int, int]:
        """The numbers of R- and Q-classifiers in the list."""
        r = len(self.classifiers.r_classifiers)
        return r, len(self.classifiers) - r


class CSQL(ClassifierSystemLearner):
    """Classifier-system Q-learning (section 4) with eq. 1-4."""

    method = "cs-ql"
    params: CSQLParams

    def __init__(self, n: int, params: CSQLParams, rng: np.random.Generator,
                 rules: tuple[RClassifier, ...] | None = None) -> None:
        super().__init__(n, params, rng, rules)
        self._gamma, self._eta, self._payoff = params.gamma, params.eta, params.payoff
        self._goal_at = layout(n).goal_start
        self.experience = Experience(SlotLayout.of(self.world_model), np.arange(len(self.world.states)))
        self.recording = True  # trials record their transitions; the sweep's are not experience
        self.backups = 0  # eq. 1-2 updates made by trials and the sweep (replay's are counted apart)
        self._where: dict[str, tuple[int, int, int, tuple[int, ...]]] = {}

    def learn(self, transition: Transition) -> None:
        """Record the transition a trial took (:class:`~csql_sim.learners.paper.replay.Experience`), then learn."""
        if self.recording:
            where = self._where.get(transition.observation)
            if where is None:
                where = self._where[transition.observation] = self._locate(transition.observation)
            s, g, lo, row = where
            self.experience.seen[g, lo + row.index(transition.action)] = True
            self.experience.steps += 1
        super().learn(transition)

    def _locate(self, message: str) -> tuple[int, int, int, tuple[int, ...]]:
        """State, goal, first slot and legal actions of a state message."""
        parsed = parse_state_message(message, self.n)
        s = self.world.state_index(parsed.state)
        return s, parsed.goal, int(self.experience.layout.lo[s]), self.world_model.table.legal[s]

    def posted(self) -> list[tuple[tuple[int, int], MatchSet]]:
        """Every posted (state, goal) with its match set (the Q-classifiers that exist)."""
        out = []
        for message, match_set in self.block.posted():
            where = self._where.get(message) or self._locate(message)
            out.append(((where[0], where[1]), match_set))
        return out

    def experience_report(self) -> dict:
        """:meth:`Experience.report <csql_sim.learners.paper.replay.Experience.report>`."""
        return self.experience.report()

    def q_greedy(self) -> np.ndarray:
        """The critic's greedy action per ``state * S + goal`` (-1: none), read without settling anything."""
        count = len(self.world.states)
        best = np.full(count * count, -1, np.int64)
        for (s, g), match_set in self.posted():
            qs = [c.q for c in match_set.candidates]
            best[s * count + g] = match_set.actions[qs.index(max(qs))]
        return best

    def replay(self) -> int:
        """A replay phase of the experienced transitions (:mod:`csql_sim.learners.paper.replay`); its backups."""
        return replay_reference(self)

    def select(self, match_set: MatchSet, temperature: float, u: float) -> int:
        """Boltzmann selection over the candidates' Q-values (eq. 3).

        A lone candidate (6 of the 22 states for n=3 have one legal action) is chosen
        without evaluating eq. 3; the uniform is consumed either way.
        """
        qs = match_set.candidates
        if len(qs) == 1:
            return 0
        return boltzmann([c.q for c in qs], temperature, u)

    def update(self, match_set: MatchSet, i: int, nxt: MatchSet | None, t: int) -> None:
        """Eq. 2's epsilon, eq. 1's Q update; |epsilon| reset, last_active = t.

        The growth of |epsilon| by ``error_increment`` per step is applied lazily from
        ``last_active`` (see :meth:`error`), so an update touches one classifier only.
        """
        self.backup(match_set.candidates[i], nxt, t, self._eta)

    def error(self, c: QClassifier) -> float:
        """|epsilon| now: the last prediction error plus the growth since (section 4)."""
        return c.error + self.params.error_increment * (self.t - c.last_active)

    def settle(self) -> None:
        """Fold the lazy |epsilon| growth into ``error`` and set strength (eq. 4) and age."""
        super().settle()
        for c in self.classifiers.q_classifiers:
            c.error = self.error(c)
            c.strength = 1.0 - c.error
            c.last_active = self.t

    @property
    def max_sweep_passes(self) -> int:
        """``sweep_passes + sweep_greedy_tail`` with ``sweep`` on, else 0."""
        p = self.params
        return p.sweep_passes + p.sweep_greedy_tail if p.sweep else 0

    def sweep(self, on_pass: Callable[[], None] | None = None) -> int:
        """With ``sweep`` on: :meth:`plan` over every pair, then the test task once greedily.

        Training thus ends on the test task, as Figure 6 was taken. Returns the planning
        steps (the test task's not counted); 0 with ``sweep`` off.

        Args:
            on_pass: called after each planning pass (progress).
        """
        if not self.params.sweep:
            return 0
        self.recording = False
        try:
            steps = self.plan(on_pass)
            run_trial(self, *self.test_indices(), 0.0)
        finally:
            self.recording = True
        return steps

    def plan(self, on_pass: Callable[[], None] | None = None) -> int:
        """Greedy planning passes over every (start, goal) pair on the world model.

        Each pass predicts every pair's greedy path with the add-delete R-classifiers and
        updates its classifiers with eq. 1-2, so each becomes active. Passes repeat until
        no update in a pass has |epsilon| above ``sweep_tolerance`` (at most
        ``sweep_passes``). With ``sweep_backup_all`` every candidate of each match set on
        the paths is backed up, not just the greedy one (:meth:`update_all`). Then
        ``sweep_greedy_tail`` greedy passes. Returns the steps taken.

        Args:
            on_pass: called after each pass (progress).
        """
        p = self.params
        before = self.t
        if p.sweep_backup_all:
            self.update = self.update_all  # learn() calls self.update; restored below
        try:
            for _ in range(p.sweep_passes):
                start_t = self.t
                self.sweep_pass()
                if on_pass is not None:
                    on_pass()
                worst = max((c.error for c in self.classifiers.q_classifiers if c.last_active >= start_t),
                            default=0.0)
                if worst <= p.sweep_tolerance:
                    break
        finally:
            self.__dict__.pop("update", None)
        for _ in range(p.sweep_greedy_tail):
            self.sweep_pass()
            if on_pass is not None:
                on_pass()
        return self.t - before

    def sweep_pass(self) -> None:
        """One greedy trial (T = 0, cap = the number of states) per pair, goal-major."""
        count = len(self.world.states)
        for goal in range(count):
            for start in range(count):
                if start != goal:
                    run_trial(self, start, goal, 0.0, cap=count)

    def update_all(self, match_set: MatchSet, i: int, nxt: MatchSet | None, t: int) -> None:
        """Dyna-style backup of every candidate (the sweep with ``sweep_backup_all``).

        The selected candidate ``i`` leads the trial on (its successor ``nxt`` is already
        posted); each other candidate's successor is predicted by the world model and
        posted in candidate order at the step's clock ``t - 1``; then every candidate, in
        candidate order, is updated with eq. 1-2 at step size ``sweep_eta``.
        """
        message = match_set.message
        goal_message = self.message(decode_code(message[self._goal_at :]), decode_code(message[self._goal_at :]))
        nexts: list[MatchSet | None] = []
        self.t = t - 1
        for j, action in enumerate(match_set.actions):
            if j == i:
                nexts.append(nxt)
                continue
            predicted = self.world_model.step(message, action)
            nexts.append(None if predicted == goal_message else self.block.post(predicted))
        self.t = t
        eta = self.params.sweep_eta
        for c, successor in zip(match_set.candidates, nexts, strict=True):
            self.backup(c, successor, t, eta)

    def backup(self, c: QClassifier, nxt: MatchSet | None, t: int, eta: float) -> None:
        """Eq. 1-2 on ``c`` towards its successor ``nxt`` (None: the goal) with step size ``eta``."""
        if nxt is None:
            target = self._payoff
        else:
            best = -INF
            for d in nxt.candidates:
                if d.q > best:
                    best = d.q
            target = self._gamma * best
        eps = target - c.q
        self.backups += 1
        c.q += eta * eps
        c.error = eps if eps >= 0.0 else -eps
        c.last_active = t
