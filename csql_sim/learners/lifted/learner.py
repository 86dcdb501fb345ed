"""LQ-CS: Q-learning of lifted Q-classifiers on small worlds, for plans at any n <= 26.

The learner holds one population of lifted Q-classifiers
(:class:`~csql_sim.core.policies.lifted_classifier.LiftedQClassifier`: a condition over the
features of a move that a **vocabulary** gives, :mod:`csql_sim.learners.lifted.vocab`, and the
move's kind), **empty at the start**. Each trial draws a world size from ``sizes`` (3..5
blocks) and a start and a goal uniformly by counting
(:func:`csql_sim.core.state.state_count.sample_state`), and runs Q-learning moves through the
world model of lifted rules (:data:`csql_sim.core.classifiers.lifted_rule.BLOCKS_WORLD`)
towards the vocabulary's target (the goal itself for generated features):

* **match and cover**: every legal move is bound to ``?x`` and ``?d``; a move that no
  classifier matches is covered by a new classifier (the vocabulary's cover; excess 0:
  optimistic, so it gets tried);
* **act** as the policy acts: with the hand empty, the move its classifiers rank first
  (least advantage of the most specific matching classifier, ties in move order), its pick
  and then its put; with the given atoms the held state is backed up after the pick and the
  put chosen again, so the decision their policy makes after a pick (atom ``holding``) is
  practised. With probability ``epsilon`` a random legal move instead, its pick and put at once;
* **update**: Q(s, m) = start(s) + excess (:mod:`csql_sim.learners.lifted.ground`: the
  vocabulary's :class:`~csql_sim.learners.lifted.ground.Costs`), so every move of the state is
  backed up through the model to its step cost plus the successor's value; the state's ground
  excess becomes the least of these minus start(s), and the classifier that matches each move
  learns the move's advantage, its Q minus the least, with rate ``beta``; it also keeps, for
  each of its ``#`` features, the mean target when that feature held and when it did not.
  Generated features learn from the task's reward alone (-1 per action, 0 at the goal); the
  given atoms from the misplaced-blocks lower bound, a move costing 1 and ``early`` per block
  still misplaced after it;
* every ``sweep`` trials, **specialization**: a classifier whose targets differ by more than
  ``tau`` between the two values of one of its ``#`` features is split on the one that separates
  them most (or on a seldom-met one costing more than ``rare_gap``, with ``rare_experience``
  below ``min_experience``); **generalization**: two classifiers of one kind whose conditions
  differ in one feature only, both with ``min_experience`` updates and excesses within ``tau / 2``,
  are merged into one with ``#`` there; with ``replay``, before these, a **sweep through the
  model**: every remembered hand-empty state is backed up once more and its successors join the
  memory (value iteration over the training goals' worlds), so the ground values stop resting on
  their start values.

The learned classifiers plan greedily for any number of blocks up to 26: no feature names a
block, so nothing is specific to the sizes trained on. This module reads no concept of the
task: the vocabulary brings what its classifiers read and what a move costs.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Collection
from dataclasses import dataclass, field

import numpy as np

from csql_sim.core.classifiers.lifted_rule import BLOCKS_WORLD
from csql_sim.core.features.formulation import parse_formulation
from csql_sim.core.features.move_features import Literal
from csql_sim.core.model.lifted_model import LiftedWorldModel
from csql_sim.core.policies.contract import Policy
from csql_sim.core.policies.feature_policy import FeaturePolicy, used_literals
from csql_sim.core.policies.lifted_classifier import LiftedQClassifier
from csql_sim.core.state.moves import Move, pick_action, put_action
from csql_sim.core.state.state_count import sample_hand_empty, sample_state
from csql_sim.core.state.world import State
from csql_sim.learners.lifted.ground import GroundValues
from csql_sim.learners.lifted.params import LiftedParams
from csql_sim.learners.lifted.rules import Rule, generalize_once, specialize
from csql_sim.learners.lifted.vocab import Vocabulary


@dataclass(frozen=True)
class LiftedRun:
    """What a training run learned and what it cost.

    Attributes:
        classifiers: the learned lifted Q-classifiers (conditions over ``atoms``).
        trials: trials run.
        steps: actions taken (a move is a pick and a put: two).
        seconds: wall time of the training loop.
        reached: trials that reached their goal.
        ground: ground Q-classifiers made on demand (the learner's working memory).
        splits: specializations made; merges: generalizations made; covered: lifted classifiers covered.
        literals: with generated features, the literals the conditions range over (else empty).
        domain: with generated features, the PDDL domain's text (else empty).
        features: with generated features, the feature space's figures (else empty).
    """

    classifiers: tuple[LiftedQClassifier, ...]
    trials: int
    steps: int
    seconds: float
    reached: int
    ground: int
    splits: int
    merges: int
    covered: int
    literals: tuple[Literal, ...] = ()
    domain: str = ""
    features: dict = field(default_factory=dict)

    @property
    def tie(self) -> Literal | None:
        """With a fitted potential, the literal that breaks the policy's ties: "the potential falls"."""
        fit = self.features.get("potential")
        return None if not fit else Literal(fit["concept"], "up" if fit["slope"] < 0 else "down")

    def policy(self, meta: dict | None = None) -> Policy:
        """The greedy policy of the learned classifiers over generated features (ties: :attr:`tie`)."""
        cut, kept = used_literals(self.classifiers, self.literals)
        return FeaturePolicy(cut, kept, parse_formulation(self.domain, "domain"), self.domain, meta, self.tie)


class _Learner:
    """One training run's classifiers and counters."""

    def __init__(self, params: LiftedParams, vocab: Vocabulary, rng: np.random.Generator) -> None:
        self.params, self.rng, self.vocab = params, rng, vocab
        self.hand = vocab.hand
        self.rules: list[Rule] = []
        self.ground = GroundValues(vocab.relations, vocab.costs, vocab.cache_relations)
        self.goals: dict[int, list[State]] = {}
        self.match: dict = {}
        self.model = LiftedWorldModel(BLOCKS_WORLD)
        self.steps = self.reached = self.splits = self.merges = self.covered = self.sweeps = 0

    def rule_for(self, i: int, j: int, bits: np.ndarray, kind: str) -> Rule:
        """The most specific matching rule (ties: smaller error), covering when none matches.

        Remembered until the next sweep: a covered rule matches only moves no rule matched.
        """
        key = self.vocab.match_key(i, j, bits, kind)
        best = self.match.get(key)
        if best is not None:
            return best
        for r in self.rules:
            if r.matches(bits, kind) and (best is None or (-r.specificity, r.error) < (-best.specificity, best.error)):
                best = r
        if best is None:
            best = Rule(self.vocab.cover(bits), kind, self.vocab.width)
            self.rules.append(best)
            self.covered += 1
        self.match[key] = best
        return best

    def draw(self, n: int) -> State:
        """A state of n blocks, uniformly (hand-empty ones only in a domain without a hand)."""
        return sample_state(n, self.rng) if self.hand else sample_hand_empty(n, self.rng)

    def trial(self) -> None:
        """One Q-learning trial: a training goal of a random size, a random start, up to 3n + 3 moves."""
        n = int(self.rng.choice(self.params.sizes))
        if n not in self.goals:
            self.goals[n] = [self.draw(n) for _ in range(self.params.goals)]
            self.vocab.prepare(n, self.goals[n], self.rng)
        pool = self.goals[n]
        start = self.draw(n)
        target = self.vocab.target(start, pool[int(self.rng.integers(len(pool)))])
        state = start
        for _ in range(3 * n + 3):
            if self.ground.final[self.ground.of(state, target)]:
                self.steps += state != target  # the last action
                self.reached += 1
                return
            state = self.step(state, target)

    def step(self, state: State, target: State) -> State:
        """One move as the policy makes it: back up, choose; after a pick, the put (module docstring).

        With a vocabulary that does not commit to its move, the held state is backed up after
        the pick and the put chosen again. With probability ``epsilon`` a random legal move is
        taken instead, its pick and put at once.
        """
        i = self.ground.of(state, target)
        move = self.backup(i)
        if self.rng.random() < self.params.epsilon:
            options = self.ground.moves_of(i)[0]
            move = options[int(self.rng.integers(len(options)))]
            if state.held is None:
                state = self.model.successor(state, pick_action(state, move.block))
                self.steps += 1
        elif state.held is None:
            state = self.model.successor(state, pick_action(state, move.block))
            self.steps += 1
            if self.hand and not self.vocab.commits:
                move = self.backup(self.ground.of(state, target))
        self.steps += 1
        return self.model.successor(state, put_action(move))

    def backup(self, i: int) -> Move:
        """The full backup of state i (its value, every move's lifted advantage); the greedy move after it.

        The greedy move is the one of least lifted advantage (ties: move order), as
        :class:`LiftedPolicy` chooses.
        """
        q = self.ground.backup(i)
        low = min(q)
        options, relations = self.ground.moves_of(i)
        rules = []
        for j, (move, bits, value) in enumerate(zip(options, relations, q, strict=True)):
            rule = self.rule_for(i, j, bits, move.kind)  # in move order: a match is decided as the last update left it
            rule.update(value - low, self.params.beta)
            rules.append(rule)
        for rule in dict.fromkeys(rules):
            at = [j for j, r in enumerate(rules) if r is rule]
            rule.add_stats(np.array([q[j] - low for j in at]), relations[at])
        ranks = [self.rule_for(i, j, bits, move.kind).advantage
                 for j, (move, bits) in enumerate(zip(options, relations, strict=True))]
        return options[ranks.index(min(ranks))]

    def replay(self) -> None:
        """A sweep through the model: back up every remembered hand-empty state again; its successors join.

        Up to the vocabulary's ``replay_passes`` passes, fewer when a pass changes no value.
        Repeated every ``sweep`` trials, these passes are value iteration over the training goals'
        worlds, spreading from the states met: the ground values (and with them the lifted
        advantages) soon measure moves exactly instead of their start values.
        """
        g = self.ground
        for _ in range(self.vocab.replay_passes):
            changed = False
            for i in range(len(g.keys)):
                if not g.final[i] and g.keys[i][0].held is None:
                    before = g.excess[i]
                    g.backup(i)
                    changed = changed or g.excess[i] != before
            if not changed:
                return

    def frozen(self) -> tuple[LiftedQClassifier, ...]:
        """The classifiers now, sorted by kind and condition."""
        return tuple(sorted((self.vocab.classifier(r) for r in self.rules), key=lambda c: (c.kind, c.condition)))

    def sweep(self) -> None:
        """Specialize the rules whose ``#`` hides a difference; merge siblings that agree."""
        p = self.params
        if p.replay:
            self.replay()
        self.sweeps += 1
        if self.sweeps > self.vocab.warmup:
            self.rules, splits = specialize(self.rules, p.tau, p.min_experience, p.rare_experience, p.rare_gap)
            self.splits += splits
        if self.vocab.fresh_stats:
            for r in self.rules:
                r.stats = None
        while (merged := generalize_once(self.rules, p.tau, p.min_experience)) is not None:
            self.rules = merged
            self.merges += 1
        self.match.clear()


def learn(params: LiftedParams, vocab: Vocabulary, rng: np.random.Generator,
          progress: Callable[[int, int], None] | None = None,
          checkpoints: Collection[int] = (),
          at_checkpoint: Callable[[int, tuple[LiftedQClassifier, ...]], None] | None = None) -> LiftedRun:
    """Learn lifted Q-classifiers over ``vocab`` from an empty population (module docstring).

    Args:
        params: the learner's parameters.
        vocab: what the classifiers read, and the costs the ground values learn from.
        rng: the run's one generator (pairs, exploration).
        progress: called with (trials done, trials) after every sweep.
        checkpoints: trial counts at which to call ``at_checkpoint``.
        at_checkpoint: called with (trials done, the classifiers then), after that trial's sweep
            if it has one; the run goes on unchanged, so a checkpoint at a multiple of ``sweep``
            gives the classifiers of a run of that many trials.
    """
    learner = _Learner(params, vocab, rng)
    t0 = time.perf_counter()
    for k in range(1, params.trials + 1):
        learner.trial()
        if k % params.sweep == 0 or k == params.trials:
            learner.sweep()
            if progress is not None:
                progress(k, params.trials)
        if k in checkpoints and at_checkpoint is not None:
            at_checkpoint(k, learner.frozen())
    literals, domain, features = vocab.summary()
    return LiftedRun(learner.frozen(), params.trials, learner.steps, time.perf_counter() - t0,
                     learner.reached, len(learner.ground.keys), learner.splits, learner.merges, learner.covered,
                     literals, domain, features)


__all__ = ["LiftedRun", "learn"]
