"""LQ-CS: Q-learning of lifted Q-classifiers on small worlds, for plans at any n <= 26.

The learner holds one population of lifted Q-classifiers
(:class:`~csql_sim.core.policies.lifted_policy.LiftedQClassifier`: a condition over the relations of
a move, :mod:`csql_sim.core.state.move_relations`, and the move's kind), **empty at the start**.
Each trial draws a world size from ``sizes`` (3..5 blocks) and a start and a goal uniformly
by counting (:func:`csql_sim.core.state.state_count.sample_state`), and runs Q-learning moves
through the world model of lifted rules (:data:`csql_sim.core.classifiers.lifted_rule.BLOCKS_WORLD`):

* **match and cover**: every legal move is bound to ``?x`` and ``?d``; a move that no
  classifier matches is covered by a new classifier whose condition is the move's
  relations exactly (excess 0: optimistic, so it gets tried);
* **act** as the policy acts: with the hand empty, the move its classifiers rank first
  (least advantage of the most specific matching classifier, ties in move order) and only
  its pick; holding the block, the held state is backed up and the put chosen again, so the
  decision the policy makes after a pick (atom ``holding``) is practised. With probability
  ``epsilon`` a random legal move instead, its pick and put at once;
* **update**: Q(s, m) = misplaced(s) + excess, one move costing 1 (and ``early`` per block
  still misplaced after it), so every move of the state is backed up through the model to
  ``1 + early * misplaced(s') + misplaced(s') + excess(s')`` (excess 0 at the goal); the
  state's ground excess becomes the least of these minus misplaced(s), and the classifier
  that matches each move learns the move's advantage, its Q minus the least, with rate
  ``beta``; it also keeps, for each of its ``#`` atoms, the mean target when that atom held
  and when it did not;
* every ``sweep`` trials, **specialization**: a classifier whose targets differ by more than
  ``tau`` between the two values of one of its ``#`` atoms is split on the atom that separates
  them most (or on a seldom-met one costing more than ``rare_gap``, with ``rare_experience``
  below ``min_experience``); **generalization**: two classifiers of one kind whose conditions
  differ in one atom only, both with ``min_experience`` updates and excesses within ``tau / 2``,
  are merged into one with ``#`` there; with ``replay``, before these, a **sweep through the
  model**: every remembered hand-empty state is backed up once more and its successors join the
  memory (value iteration over the training goals' worlds), so the ground values stop resting on
  the misplaced-blocks lower bound, under which a put onto a block that must move again ties
  with the table put.

The learned classifiers plan greedily (:class:`~csql_sim.core.policies.lifted_policy.LiftedPolicy`)
for any number of blocks up to 26: no atom names a block, so nothing is specific to the
sizes trained on.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Collection
from dataclasses import dataclass, field, fields

import numpy as np

from csql_sim.core.classifiers.lifted_rule import BLOCKS_WORLD
from csql_sim.core.features.formulation import BUILTIN, MAX_DOMAIN_BYTES, load_formulation, parse_formulation
from csql_sim.core.features.move_features import Literal
from csql_sim.core.model.lifted_model import LiftedWorldModel
from csql_sim.core.policies.feature_policy import FeaturePolicy, used_literals
from csql_sim.core.policies.lifted_policy import LiftedPolicy, LiftedQClassifier
from csql_sim.core.state.move_relations import ATOMS, target_goal
from csql_sim.core.state.moves import Move, pick_action, put_action
from csql_sim.core.state.state_count import sample_hand_empty, sample_state
from csql_sim.core.state.world import State
from csql_sim.infra.assets import asset_text
from csql_sim.infra.files import read_text_file
from csql_sim.learners.lifted.ground import GroundValues
from csql_sim.learners.lifted.rules import Rule, generalize_once, specialize
from csql_sim.learners.lifted.vocab import GeneratedFeatures, GivenAtoms, Vocabulary
from csql_sim.learners.paper.params import ParamsError

TRAIN_SIZES = (3, 4, 5)
"""The world sizes a lifted learner may train on."""
FEATURES = ("given", "generated")
"""What the lifted classifiers may read."""
READ_ATOMS = tuple(a for a in ATOMS if a != "least-stuck(?x)")
"""The given atoms the classifiers read by default: all but ``least-stuck(?x)`` (:class:`LiftedParams`)."""


@dataclass(frozen=True)
class LiftedParams:
    """Parameters of LQ-CS; every one with its default and range.

    Attributes:
        trials: training trials (one start/goal pair each). Range >= 1; default 3000.
        sizes: world sizes drawn uniformly per trial. Each of 3, 4, 5; default (5,): the largest
            small world has the deadlocks between towers that large worlds are made of.
        goals: training goals per size, drawn once when the size is first met. Range >= 1; default 40,
            and 200 with generated features in the move domain (thousands of features need more
            situations to tell the general ones from the accidents of a few goals; in a domain
            with a hand, six times more literals make the feature table of 200 goals about 5 GB).
        beta: learning rate of the lifted advantages and errors. Range (0, 1]; default 0.02.
        epsilon: probability of a random legal move. Range [0, 1); default 0.5 (spreads the updates).
        tau: moves of advantage that tell two conditions apart. Range > 0; default 0.05 (near-ties
            decide the detours of large worlds, so only conditions that agree closely are merged).
        min_experience: updates before a classifier is split or merged. Range >= 1; default 30
            with the given atoms, 100 with generated features (a split chosen among thousands
            needs more evidence).
        sweep: trials between specialization and generalization sweeps. Range >= 1; default 100 with the
            given atoms, 300 with generated features: their split statistics restart every sweep, so a
            sweep must give both values of a decisive literal ``min_experience`` updates.
        rare_experience: updates on a literal's rarer value for a rare split (gap above ``rare_gap``,
            :func:`~csql_sim.learners.lifted.rules.split_position`). Range 1..``min_experience``; default
            ``min_experience``, none (20 fixed one 4-operator seed and broke two: ``docs/features.md``).
        rare_gap: moves of advantage a rare split needs. Range > ``tau``; default 1.0 (a wasted move).
        replay: whether every sweep also backs up the remembered ground values through the
            world model (:meth:`_Learner.replay`). True or False; default True.
        early: the cost of a move per block still misplaced after it, in moves. Range [0, 1);
            default 0.02: too small to trade a move for at five blocks, it prefers, among plans of
            one length, the one that places blocks sooner.
        features: what the classifiers read: ``given`` (hand-written atoms, those of ``atoms``) or
            ``generated`` (features built from the domain's predicates,
            :mod:`~csql_sim.learners.lifted.vocab`). Default ``given``.
        domain: the formulation of ``generated`` features: ``4op``, ``move`` or a PDDL domain
            file (:func:`~csql_sim.core.features.formulation.load_formulation`). Default ``4op``.
        complexity: the grammar's complexity bound K for ``generated``. Range 1..10; default 8.
        sample: (state, goal) pairs the generated features are pruned on (with every move of
            each). Range 10..5000; default 200.
        atoms: with ``given``, the atoms the classifiers may read; an atom left out is ``#`` in
            every condition. A non-empty subset of :data:`ATOMS`; default :data:`READ_ATOMS`, all
            but ``least-stuck(?x)``: at five blocks a least-stuck table move outside the ``cover`` is
            as short as a cover move (44% of them waste a move at twelve blocks), so with both
            atoms the seeds ranked them differently; without it every seed prefers the cover.
    """

    trials: int = 3000
    sizes: tuple[int, ...] = (5,)
    goals: int | None = None
    beta: float = 0.02
    epsilon: float = 0.5
    tau: float = 0.05
    min_experience: int | None = None
    sweep: int | None = None
    rare_experience: int | None = None
    rare_gap: float = 1.0
    replay: bool = True
    early: float = 0.02
    features: str = "given"
    domain: str = "4op"
    complexity: int = 8
    sample: int = 200
    atoms: tuple[str, ...] = READ_ATOMS

    def __post_init__(self) -> None:
        generated = self.features == "generated"
        if self.goals is None:
            object.__setattr__(self, "goals", 200 if generated and self.domain == "move" else 40)
        if self.sweep is None:
            object.__setattr__(self, "sweep", 300 if generated else 100)
        if self.min_experience is None:
            object.__setattr__(self, "min_experience", 100 if generated else 30)
        if self.rare_experience is None:
            object.__setattr__(self, "rare_experience", self.min_experience)
        checks = {
            "trials": isinstance(self.trials, int) and self.trials >= 1,
            "sizes": bool(self.sizes) and all(isinstance(n, int) and n in TRAIN_SIZES for n in self.sizes),
            "goals": isinstance(self.goals, int) and self.goals >= 1,
            "beta": 0 < self.beta <= 1,
            "epsilon": 0 <= self.epsilon < 1,
            "tau": 0 < self.tau < math.inf,
            "min_experience": isinstance(self.min_experience, int) and self.min_experience >= 1,
            "sweep": isinstance(self.sweep, int) and self.sweep >= 1,
            "rare_experience": isinstance(self.rare_experience, int) and isinstance(self.min_experience, int)
            and 1 <= self.rare_experience <= self.min_experience,
            "rare_gap": isinstance(self.rare_gap, (int, float)) and self.tau < self.rare_gap < math.inf,
            "replay": isinstance(self.replay, bool),
            "early": 0 <= self.early < 1,
            "features": self.features in FEATURES,
            "domain": isinstance(self.domain, str) and bool(self.domain),
            "complexity": isinstance(self.complexity, int) and 1 <= self.complexity <= 10,
            "sample": isinstance(self.sample, int) and 10 <= self.sample <= 5000,
            "atoms": bool(self.atoms) and all(a in ATOMS for a in self.atoms),
        }
        bad = [name for name, ok in checks.items() if not ok]
        if bad:
            raise ParamsError(f"lifted learner parameter {bad[0]}={getattr(self, bad[0])!r} is out of range "
                              "(see LiftedParams)")

    def as_dict(self) -> dict:
        """The parameters as plain values (the generated features' own only when they are used)."""
        own = ("atoms",) if self.features == "generated" else ("features", "domain", "complexity", "sample")
        return {f.name: list(v) if isinstance(v := getattr(self, f.name), tuple) else v for f in fields(self)
                if f.name not in own}


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

    def policy(self, meta: dict | None = None) -> LiftedPolicy | FeaturePolicy:
        """The greedy policy of the learned classifiers."""
        if not self.literals:
            return LiftedPolicy(self.classifiers, meta)
        cut, kept = used_literals(self.classifiers, self.literals)
        return FeaturePolicy(cut, kept, parse_formulation(self.domain, "domain"), self.domain, meta)


def vocabulary_of(params: LiftedParams) -> Vocabulary:
    """The vocabulary the parameters name."""
    if params.features == "given":
        return GivenAtoms(params.atoms)
    form = load_formulation(params.domain)
    domain = asset_text("domains", BUILTIN[params.domain]) if params.domain in BUILTIN else \
        read_text_file(params.domain, MAX_DOMAIN_BYTES, "PDDL domain")
    return GeneratedFeatures(form, domain, params.complexity, params.sample)


class _Learner:
    """One training run's classifiers and counters."""

    def __init__(self, params: LiftedParams, rng: np.random.Generator) -> None:
        self.params, self.rng = params, rng
        self.vocab = vocabulary_of(params)
        self.hand = not isinstance(self.vocab, GeneratedFeatures) or self.vocab.form.hand
        self.rules: list[Rule] = []
        self.ground = GroundValues(self.vocab.relations, params.early, self.vocab.cache_relations)
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
        target = target_goal(start, pool[int(self.rng.integers(len(pool)))])
        state = start
        for _ in range(3 * n + 3):
            if state == target:
                self.reached += 1
                return
            state = self.step(state, target)

    def step(self, state: State, target: State) -> State:
        """One move as the policy makes it: back up, choose; after a pick, back up the held state and choose the put.

        With probability ``epsilon`` a random legal move is taken instead, its pick and put at once.
        Without a hand (the move domain) a move is one action: its pick and put at once.
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
            if self.hand:
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
        """A sweep through the model: back up every remembered hand-empty state once more; its successors join.

        Repeated every ``sweep`` trials, these passes are value iteration over the training goals'
        worlds, spreading from the states met: the ground values (and with them the lifted
        advantages) soon measure moves exactly instead of the misplaced-blocks lower bound.
        """
        g = self.ground
        for i in range(len(g.keys)):
            if g.low[i] and g.keys[i][0].held is None:  # not the target, hand empty
                g.backup(i)

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


def train_lifted(params: LiftedParams, rng: np.random.Generator,
                 progress: Callable[[int, int], None] | None = None,
                 checkpoints: Collection[int] = (),
                 at_checkpoint: Callable[[int, tuple[LiftedQClassifier, ...]], None] | None = None) -> LiftedRun:
    """Learn lifted Q-classifiers from an empty population (module docstring).

    Args:
        params: the learner's parameters.
        rng: the run's one generator (pairs, exploration).
        progress: called with (trials done, trials) after every sweep.
        checkpoints: trial counts at which to call ``at_checkpoint``.
        at_checkpoint: called with (trials done, the classifiers then), after that trial's sweep
            if it has one; the run goes on unchanged, so a checkpoint at a multiple of ``sweep``
            gives the classifiers of a run of that many trials.
    """
    learner = _Learner(params, rng)
    t0 = time.perf_counter()
    for k in range(1, params.trials + 1):
        learner.trial()
        if k % params.sweep == 0 or k == params.trials:
            learner.sweep()
            if progress is not None:
                progress(k, params.trials)
        if k in checkpoints and at_checkpoint is not None:
            at_checkpoint(k, learner.frozen())
    vocab = learner.vocab
    generated = isinstance(vocab, GeneratedFeatures) and vocab.space is not None
    features = {} if not generated else {
        "formulation": vocab.form.name, "complexity": vocab.space.complexity, "candidates": vocab.space.candidates,
        "concepts": vocab.space.generated, "literals": len(vocab.space.literals)}
    return LiftedRun(learner.frozen(), params.trials, learner.steps, time.perf_counter() - t0,
                     learner.reached, len(learner.ground.keys), learner.splits, learner.merges, learner.covered,
                     vocab.literals if generated else (), vocab.domain if generated else "", features)


__all__ = ["ATOMS", "READ_ATOMS", "TRAIN_SIZES", "LiftedParams", "LiftedRun", "train_lifted"]
