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
* every ``sweep`` trials, **specialization**: a classifier whose targets differ by more
  than ``tau`` between the two values of one of its ``#`` atoms is split on the atom that
  separates them most; **generalization**: two classifiers of one kind whose conditions
  differ in one atom only, both with ``min_experience`` updates and excesses within
  ``tau / 2``, are merged into one with ``#`` there; with ``replay``, before these, a
  **sweep through the model**: every remembered hand-empty state is backed up once more and
  its successors join the memory (value iteration over the training goals' worlds), so the
  ground values stop resting on the misplaced-blocks lower bound, under which a put onto a
  block that must move again ties with the table put.

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
from csql_sim.core.model.lifted_model import LiftedWorldModel
from csql_sim.core.policies.lifted_policy import LiftedPolicy, LiftedQClassifier, condition_holds
from csql_sim.core.state.move_relations import (
    ATOMS,
    Move,
    pick_action,
    put_action,
    target_goal,
)
from csql_sim.core.state.state_count import sample_state
from csql_sim.core.state.world import State
from csql_sim.learners.lifted_ground import GroundValues
from csql_sim.learners.params import ParamsError

TRAIN_SIZES = (3, 4, 5)
"""The world sizes a lifted learner may train on."""


@dataclass(frozen=True)
class LiftedParams:
    """Parameters of LQ-CS; every one with its default and range.

    Attributes:
        trials: training trials (one start/goal pair each). Range >= 1; default 3000.
        sizes: world sizes drawn uniformly per trial. Each of 3, 4, 5; default (5,): the
            largest small world has the situations (deadlocks between towers) that large
            worlds are made of.
        goals: training goals per size, drawn once when the size is first met. Range >= 1; default 40.
        beta: learning rate of the lifted advantages and errors. Range (0, 1]; default 0.02.
        epsilon: probability of a random legal move (wide exploration spreads the updates
            over the states). Range [0, 1); default 0.5.
        tau: moves of advantage that tell two conditions apart. Range > 0; default 0.05
            (near-ties decide the detours of large worlds, so only conditions that agree
            closely are merged).
        min_experience: updates before a classifier is split or merged. Range >= 1; default 30.
        sweep: trials between specialization and generalization sweeps. Range >= 1; default 100.
        replay: whether every sweep also backs up the remembered ground values through the
            world model (:meth:`_Learner.replay`). True or False; default True.
        early: the cost of a move per block still misplaced after it, in moves. Range [0, 1);
            default 0.02: too small to trade a move for it at five blocks, it makes the learner
            prefer, among plans of one length, the one that places blocks sooner (a constructive
            move before a table move that five blocks cannot tell apart from it).
    """

    trials: int = 3000
    sizes: tuple[int, ...] = (5,)
    goals: int = 40
    beta: float = 0.02
    epsilon: float = 0.5
    tau: float = 0.05
    min_experience: int = 30
    sweep: int = 100
    replay: bool = True
    early: float = 0.02

    def __post_init__(self) -> None:
        checks = {
            "trials": isinstance(self.trials, int) and self.trials >= 1,
            "sizes": bool(self.sizes) and all(isinstance(n, int) and n in TRAIN_SIZES for n in self.sizes),
            "goals": isinstance(self.goals, int) and self.goals >= 1,
            "beta": 0 < self.beta <= 1,
            "epsilon": 0 <= self.epsilon < 1,
            "tau": 0 < self.tau < math.inf,
            "min_experience": isinstance(self.min_experience, int) and self.min_experience >= 1,
            "sweep": isinstance(self.sweep, int) and self.sweep >= 1,
            "replay": isinstance(self.replay, bool),
            "early": 0 <= self.early < 1,
        }
        bad = [name for name, ok in checks.items() if not ok]
        if bad:
            raise ParamsError(f"lifted learner parameter {bad[0]}={getattr(self, bad[0])!r} is out of range "
                              "(see LiftedParams)")

    def as_dict(self) -> dict:
        """The parameters as plain values."""
        return {f.name: list(v) if isinstance(v := getattr(self, f.name), tuple) else v for f in fields(self)}


@dataclass
class _Rule:
    """A lifted classifier being learned: its statistics and, per ``#`` atom, advantage sums by the atom's value."""

    condition: str
    kind: str
    advantage: float = 0.0
    error: float = 0.0
    experience: int = 0
    split: dict[int, list[float]] = field(default_factory=dict)

    def matches(self, bits: tuple[int, ...], kind: str) -> bool:
        return kind == self.kind and condition_holds(self.condition, bits)

    def update(self, advantage: float, bits: tuple[int, ...], beta: float) -> None:
        """One update of the advantage and its error (MAM: plain averages for the first 1/beta updates)."""
        self.experience += 1
        rate = max(beta, 1.0 / self.experience)
        self.error += rate * (abs(advantage - self.advantage) - self.error)
        self.advantage += rate * (advantage - self.advantage)
        for i, c in enumerate(self.condition):
            if c == "#":
                sums = self.split.setdefault(i, [0.0, 0, 0.0, 0])
                sums[2 * bits[i]] += advantage
                sums[2 * bits[i] + 1] += 1

    def frozen(self) -> LiftedQClassifier:
        return LiftedQClassifier(self.condition, self.kind, round(self.advantage, 3), round(self.error, 3),
                                 self.experience)


@dataclass(frozen=True)
class LiftedRun:
    """What a training run learned and what it cost.

    Attributes:
        classifiers: the learned lifted Q-classifiers.
        trials: trials run.
        steps: actions taken (a move is a pick and a put: two).
        seconds: wall time of the training loop.
        reached: trials that reached their goal.
        ground: ground Q-classifiers made on demand (the learner's working memory).
        splits: specializations made; merges: generalizations made; covered: lifted classifiers covered.
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

    def policy(self, meta: dict | None = None) -> LiftedPolicy:
        """The greedy policy of the learned classifiers."""
        return LiftedPolicy(self.classifiers, meta)


class _Learner:
    """One training run's classifiers and counters."""

    def __init__(self, params: LiftedParams, rng: np.random.Generator) -> None:
        self.params, self.rng = params, rng
        self.rules: list[_Rule] = []
        self.ground = GroundValues(params.early)
        self.goals: dict[int, list[State]] = {}
        self.match: dict[tuple[tuple[int, ...], str], _Rule] = {}
        self.model = LiftedWorldModel(BLOCKS_WORLD)
        self.steps = self.reached = self.splits = self.merges = self.covered = 0

    def rule_for(self, bits: tuple[int, ...], kind: str) -> _Rule:
        """The most specific matching rule (ties: smaller error), covering when none matches.

        Remembered until the next sweep: a covered rule matches its own relations only.
        """
        key = (bits, kind)
        best = self.match.get(key)
        if best is not None:
            return best
        for r in self.rules:
            if r.matches(bits, kind) and (best is None or (r.condition.count("#"), r.error)
                                          < (best.condition.count("#"), best.error)):
                best = r
        if best is None:
            best = _Rule("".join(map(str, bits)), kind)
            self.rules.append(best)
            self.covered += 1
        self.match[key] = best
        return best

    def trial(self) -> None:
        """One Q-learning trial: a training goal of a random size, a random start, up to 3n + 3 moves."""
        n = int(self.rng.choice(self.params.sizes))
        if n not in self.goals:
            self.goals[n] = [sample_state(n, self.rng) for _ in range(self.params.goals)]
        pool = self.goals[n]
        start = sample_state(n, self.rng)
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
        for move, bits, value in zip(options, relations, q, strict=True):
            self.rule_for(bits, move.kind).update(value - low, bits, self.params.beta)
        ranks = [self.rule_for(bits, move.kind).advantage for move, bits in zip(options, relations, strict=True)]
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
        return tuple(r.frozen() for r in sorted(self.rules, key=lambda r: (r.kind, r.condition)))

    def sweep(self) -> None:
        """Specialize the rules whose ``#`` hides a difference; merge siblings that agree."""
        if self.params.replay:
            self.replay()
        self._specialize()
        while self._generalize_once():
            pass
        self.match.clear()

    def _specialize(self) -> None:
        p = self.params
        out = []
        for r in self.rules:
            best, gap = None, p.tau
            for i, (s0, c0, s1, c1) in r.split.items():
                if min(c0, c1) >= p.min_experience and abs(s0 / c0 - s1 / c1) > gap:
                    best, gap = i, abs(s0 / c0 - s1 / c1)
            if best is None or r.experience < p.min_experience:
                out.append(r)
                continue
            s0, c0, s1, c1 = r.split[best]
            for value, total, count in (("0", s0, c0), ("1", s1, c1)):
                cond = r.condition[:best] + value + r.condition[best + 1:]
                out.append(_Rule(cond, r.kind, total / count, r.error, int(count)))
            self.splits += 1
        self.rules = out

    def _generalize_once(self) -> bool:
        p = self.params
        for i, a in enumerate(self.rules):
            for b in self.rules[i + 1:]:
                pos = _sibling_position(a, b)
                if pos is None or min(a.experience, b.experience) < p.min_experience \
                        or abs(a.advantage - b.advantage) >= p.tau / 2:
                    continue
                total = a.experience + b.experience
                merged = _Rule(a.condition[:pos] + "#" + a.condition[pos + 1:], a.kind,
                               (a.advantage * a.experience + b.advantage * b.experience) / total,
                               max(a.error, b.error), total)
                self.rules = [r for r in self.rules if r is not a and r is not b] + [merged]
                self.merges += 1
                return True
        return False


def _sibling_position(a: _Rule, b: _Rule) -> int | None:
    """The one atom where a and b differ as 0 and 1 (same kind, same elsewhere), else None."""
    if a.kind != b.kind:
        return None
    diff = [i for i, (x, y) in enumerate(zip(a.condition, b.condition, strict=True)) if x != y]
    if len(diff) != 1 or {a.condition[diff[0]], b.condition[diff[0]]} != {"0", "1"}:
        return None
    return diff[0]


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
    return LiftedRun(learner.frozen(), params.trials, learner.steps, time.perf_counter() - t0,
                     learner.reached, len(learner.ground.keys), learner.splits, learner.merges, learner.covered)


__all__ = ["ATOMS", "TRAIN_SIZES", "LiftedParams", "LiftedRun", "train_lifted"]
