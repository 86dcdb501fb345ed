"""XCS-QL: CS-QL that generalizes while it learns, with a population of ``#`` Q-classifiers (XCS-style).

CS-QL (:class:`~csql_sim.learners.paper.cs_ql.CSQL`) runs as before and is the *critic*: its
trials on the world model and its backups (eq. 1-2) learn a Q-value per state, goal and
candidate action. Beside it lives a **population** of generalized Q-classifiers over the
goal form of the message (:mod:`csql_sim.core.state.goal_message`), the *actors*; they alone
decide the plans the learner writes. Every :attr:`ActorParams.epoch` trials (and after
the sweep) the population is revised over the (state, goal) pairs visited so far, as a
supervised XCS (UCS, Bernado-Mansilla and Garrell 2003) does:

* **accuracy-based fitness**: an actor's experience is the number of visited pairs it
  matches where its action is a candidate; its accuracy the fraction of those where the
  critic rates its action greedy (Q within 1e-9 of the best); fitness = accuracy ** nu;
* **covering with #**: a visited pair that no accurate actor decides rightly gets a new
  actor: its message with each character replaced by ``#`` with probability ``p_hash``,
  and one of the critic's greedy actions there;
* **specialization on error**: an inaccurate actor (experience at least ``theta``) gets a
  child with one more specified character, taken from a pair where it was right at a
  position where that pair differs from one where it was wrong;
* **subsumption**: an accurate, experienced actor absorbs (numerosity) every actor of the
  same action whose condition it generalizes;
* **deletion**: above ``max_population`` actors, the lowest fitness go.

The rule base it writes is the population **condensed** into a default hierarchy
(:mod:`csql_sim.core.policies.default_hierarchy`): repeatedly the actor that decides the most
still-open pairs and is right on every open pair it matches, then literals and actors are
dropped while the list stays right (the offline compaction's pruning). A pair no actor can
decide rightly is covered by its own specific actor.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import RClassifier
from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.policies.default_hierarchy import DefaultHierarchy
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.core.state.goal_message import WILDCARD, GoalForm
from csql_sim.core.state.goal_message_index import pair_messages
from csql_sim.core.state.message import action_messages, parse_state_message
from csql_sim.learners.generalize.compaction import TOLERANCE, Problem, Rule, condition_of, decision_list, simplify
from csql_sim.learners.paper.cs_ql import CSQL
from csql_sim.learners.paper.learner import TEST_EVERY, Curve, Transition
from csql_sim.learners.paper.params import CSQLParams
from csql_sim.learners.paper.trial import run_training


@dataclass(frozen=True)
class ActorParams:
    """The population's parameters (XCS names where XCS has them).

    Attributes:
        epoch: trials between revisions of the population.
        p_hash: probability of ``#`` per character when covering (XCS's P#).
        theta: experience before an inaccurate actor is specialized (XCS's theta_GA).
        theta_sub: experience before an accurate actor subsumes (XCS's theta_sub).
        nu: fitness exponent (XCS's nu).
        max_population: actors kept at most (XCS's N).
        cover_per_epoch: most pairs covered per revision.
        specialize_per_epoch: most inaccurate actors specialized per revision (the most
            experienced first).
        final_revisions: revisions after the sweep (replaying the visited pairs).
    """

    epoch: int = 250
    p_hash: float = 0.9
    theta: int = 2
    theta_sub: int = 20
    nu: float = 5.0
    max_population: int = 1500
    cover_per_epoch: int = 40
    specialize_per_epoch: int = 200
    final_revisions: int = 60


class XCSQL(CSQL):
    """CS-QL's critic plus an XCS-style population of goal-form ``#`` Q-classifiers (see the module)."""

    method = "xcs-ql"

    def __init__(self, n: int, params: CSQLParams, rng: np.random.Generator,
                 rules: tuple[RClassifier, ...] | None = None, actor: ActorParams | None = None) -> None:
        super().__init__(n, params, rng, rules)
        self.actor = actor or ActorParams()
        self.form = GoalForm(n)
        self.rng = rng
        self.messages = pair_messages(self.form)
        self.count = len(self.world.states)
        self.legal = self.world_model.table.next_state >= 0
        self.visited = np.zeros(self.count * self.count, bool)
        self.population: dict[tuple[str, int], int] = {}  # (condition, action) -> numerosity
        self.revisions = 0
        self._pair_of: dict[str, int] = {}
        self._condensed: list[QClassifier] | None = None

    # -- experience ----------------------------------------------------------------------
    def learn(self, transition: Transition) -> None:
        """CS-QL's update; the pair is remembered for the population's revisions."""
        super().learn(transition)
        key = self._pair_of.get(transition.observation)
        if key is None:
            parsed = parse_state_message(transition.observation, self.n)
            key = self._pair_of[transition.observation] = (
                self.world.state_index(parsed.state) * self.count + parsed.goal)
        self.visited[key] = True
        self._condensed = None

    def train(self, trials: int, on_trial: Callable[[int], None] | None = None,
              test_every: int = TEST_EVERY) -> Curve:
        """CS-QL's training; the population is revised every ``epoch`` trials."""
        def each(k: int) -> None:
            if (k + 1) % self.actor.epoch == 0:
                self.revise()
            if on_trial is not None:
                on_trial(k)

        return run_training(self, trials, test_every, each)

    def sweep(self, on_pass: Callable[[], None] | None = None) -> int:
        """CS-QL's sweep, then ``final_revisions`` revisions over the visited pairs."""
        steps = super().sweep(on_pass)
        for _ in range(self.actor.final_revisions):
            if not self.revise():
                break
        return steps

    # -- the population ------------------------------------------------------------------
    def _greedy(self, pairs: np.ndarray) -> np.ndarray:
        """``[len(pairs), actions]``: the critic's greedy actions of each pair (none: no classifier yet)."""
        out = np.zeros((len(pairs), len(self.world.actions)), bool)
        codes = {m: i for i, m in enumerate(action_messages(self.n))}
        for row, key in enumerate(pairs.tolist()):
            qs = self.classifiers.q_for(self.message(*divmod(key, self.count)))
            if qs:
                best = max(c.q for c in qs.values())
                for action, c in qs.items():
                    out[row, codes[action]] = c.q >= best - TOLERANCE
        return out

    def _stats(self, pairs: np.ndarray, greedy: np.ndarray) -> dict[tuple[str, int], tuple[np.ndarray, np.ndarray]]:
        """Per actor, the masks over ``pairs`` where it matches a candidate, and where it is wrong there."""
        rows = self.messages[pairs]
        legal = self.legal[pairs // self.count]
        out = {}
        for cond, action in self.population:
            hit = legal[:, action].copy()
            for pos, ch in enumerate(cond):
                if ch != WILDCARD:
                    hit &= rows[:, pos] == ord(ch)
            out[(cond, action)] = (hit, hit & ~greedy[:, action])
        return out

    def revise(self) -> bool:
        """One revision over the visited pairs (see the module); False when nothing changed."""
        self.revisions += 1
        pairs = np.flatnonzero(self.visited)
        greedy = self._greedy(pairs)
        stats = self._stats(pairs, greedy)
        before = set(self.population)
        self._subsume(stats)
        decided = np.zeros(len(pairs), bool)
        for key, (hit, wrong) in stats.items():
            if key in self.population and not wrong.any():
                decided |= hit
        self._cover(pairs, greedy, ~decided & greedy.any(axis=1))
        self._specialize(pairs, stats)
        self._delete(stats)
        self._condensed = None
        return set(self.population) != before

    def _cover(self, pairs: np.ndarray, greedy: np.ndarray, open_: np.ndarray) -> None:
        rows = np.flatnonzero(open_)
        if len(rows) > self.actor.cover_per_epoch:
            rows = self.rng.choice(rows, self.actor.cover_per_epoch, replace=False)
        for row in rows.tolist():
            message = bytes(self.messages[pairs[row]]).decode("ascii")
            keep = self.rng.random(len(message)) >= self.actor.p_hash
            cond = "".join(ch if k else WILDCARD for ch, k in zip(message, keep, strict=True))
            action = int(self.rng.choice(np.flatnonzero(greedy[row])))
            self._add(cond, action)

    def _specialize(self, pairs: np.ndarray, stats: dict) -> None:
        rows = self.messages[pairs]
        wrongs = [(int(hit.sum()), key) for key, (hit, wrong) in stats.items()
                  if wrong.any() and hit.sum() >= self.actor.theta and key in self.population]
        wrongs.sort(key=lambda x: x[0], reverse=True)
        for _, (cond, action) in wrongs[: self.actor.specialize_per_epoch]:
            hit, wrong = stats[(cond, action)]
            right = np.flatnonzero(hit & ~wrong)
            if not len(right):
                del self.population[(cond, action)]  # never right: no specialization can help
                continue
            w = rows[int(self.rng.choice(np.flatnonzero(wrong)))]
            c = rows[int(self.rng.choice(right))]
            free = [p for p, ch in enumerate(cond) if ch == WILDCARD and w[p] != c[p]]
            if free:
                pos = int(self.rng.choice(free))
                self._add(cond[:pos] + chr(c[pos]) + cond[pos + 1:], action)

    def _subsume(self, stats: dict) -> None:
        keys = list(self.population)
        if not keys:
            return
        conds = np.frombuffer("".join(k[0] for k in keys).encode("ascii"), np.uint8).reshape(len(keys), -1)
        acts = np.array([k[1] for k in keys])
        alive = np.ones(len(keys), bool)
        accurate = [i for i, k in enumerate(keys)
                    if k in stats and stats[k][0].sum() >= self.actor.theta_sub and not stats[k][1].any()]
        accurate.sort(key=lambda i: keys[i][0].count(WILDCARD), reverse=True)
        wild = ord(WILDCARD)
        for g in accurate:
            if not alive[g]:
                continue
            general = conds[g]
            covered = alive & (acts == acts[g]) & ((general == wild) | (general == conds)).all(axis=1)
            covered[g] = False
            for i in np.flatnonzero(covered).tolist():
                self.population[keys[g]] += self.population.pop(keys[i])
            alive &= ~covered

    def _delete(self, stats: dict) -> None:
        excess = len(self.population) - self.actor.max_population
        if excess <= 0:
            return

        def fitness(key: tuple[str, int]) -> float:
            hit, wrong = stats.get(key, (np.ones(1, bool), np.zeros(1, bool)))
            seen = max(int(hit.sum()), 1)
            return (1.0 - wrong.sum() / seen) ** self.actor.nu

        for key in sorted(self.population, key=fitness)[:excess]:
            del self.population[key]

    def _add(self, cond: str, action: int) -> None:
        cond = "S" + cond[1:self.form.tag_pos] + "G" + cond[self.form.tag_pos + 1:]
        self.population[(cond, action)] = self.population.get((cond, action), 0) + 1

    # -- what was learned ----------------------------------------------------------------
    def condensed(self) -> list[QClassifier]:
        """The population condensed into a default hierarchy (see the module); memoized until the next step."""
        if self._condensed is None:
            self._condensed = self._condense()
        return self._condensed

    def _condense(self) -> list[QClassifier]:
        pairs = np.flatnonzero(self.visited)
        greedy = np.zeros((self.count * self.count, len(self.world.actions)), bool)
        greedy[pairs] = self._greedy(pairs)
        problem = Problem(self.form, greedy, self.legal)
        rules = [Rule(tuple((p, ord(ch)) for p, ch in enumerate(cond) if (p, ord(ch)) in problem.literal), a)
                 for cond, a in self.population]
        chosen = decision_list(problem, rules)
        chosen = simplify(problem, chosen)
        messages = action_messages(self.n)
        return [QClassifier(condition_of(r, self.form), messages[r.action], q=1.0, strength=1.0) for r in chosen]

    def greedy_table(self) -> GreedyTable:
        """The condensed population's decisions for every pair (the default hierarchy's rule)."""
        return GreedyTable(self.n, DefaultHierarchy(self.form, self.condensed(), self.world_model).decisions().best)

    def rulebase(self, meta: dict | None = None) -> RuleBase:
        """The condensed population as a goal-form rule base (the critic's table is not written)."""
        qs = self.condensed()
        info = {**self.form.meta(), "population": len(self.population),
                "population_numerosity": int(sum(self.population.values())),
                "critic_q_classifiers": len(self.classifiers.q_classifiers), "revisions": self.revisions,
                "action_selection": "the first Q-classifier (list order) that matches and proposes a candidate"}
        return RuleBase(blocks=self.n, classifiers=list(qs), meta={**(meta or {}), **info})

    def counts(self) -> tuple[int, int]:
        """No R-classifiers are written; the condensed Q-classifiers."""
        return 0, len(self.condensed())

