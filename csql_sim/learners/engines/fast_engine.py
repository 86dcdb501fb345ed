"""The array-backed CS-QL engine: the reference engine's trajectory, compiled.

:class:`FastCSQL` is one more engine behind the :class:`~csql_sim.learners.paper.learner.Learner`
contract. It trains exactly as :class:`csql_sim.learners.paper.cs_ql.CSQL` does (same
uniforms consumed in the same order, same floating-point operations in the same order,
same classifier creation order), so the same seed writes the same rule file byte for
byte. Its state is a handful of numpy arrays (see :mod:`csql_sim.learners.engines.fast_kernels`)
instead of classifier objects, and its loops are compiled with numba.

The domain knowledge is the same: the candidates of a state and their predicted
successors are read off the R-classifiers (the precondition rules matched and the
add-delete rule applied by :class:`~csql_sim.core.model.world_model.WorldModel`), once per
state, when the engine is built. Nothing comes from the world's own transition table.
"""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.files.rulebase import RuleBase, dumps, is_npz
from csql_sim.core.files.rulebase_npz import arrays_to_bytes
from csql_sim.core.model.search import greedy_argmax
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.core.state.message import format_action_message, format_state_message, goal_code, layout
from csql_sim.infra.errors import CsqlError
from csql_sim.learners.engines.kernel_calls import HELD_SIGNALS as HELD_SIGNALS  # re-exported
from csql_sim.learners.engines.kernel_calls import call_kernel
from csql_sim.learners.paper.learner import BATCH, TEST_EVERY, Curve, Learner
from csql_sim.learners.paper.params import CSQLParams


class _Kernels:
    """The compiled kernels, imported on first use: importing numba costs most of a second."""

    def __getattr__(self, name: str):
        from csql_sim.learners.engines import fast_kernels

        return getattr(fast_kernels, name)


fk = _Kernels()
MAX_FAST_BLOCKS = 6
STEPS_PER_CALL = 250_000
"""Steps one compiled call of :meth:`FastCSQL.train` may take before it returns to Python
(it pauses between trials, so plus those under way): some 50 ms at 5 million steps a second."""
COMPENSATED_SUM = sys.version_info >= (3, 12)
"""Python 3.12 made ``sum()`` of floats compensated; the kernels follow the running Python."""
@dataclass(frozen=True)
class ModelArrays:
    """The R-classifiers' answers for every state, as arrays.

    Attributes:
        lo: ``lo[s] .. lo[s + 1]`` index state ``s``'s candidates in ``action`` and ``nxt``.
        action: each candidate's action index (ascending, the stable action order).
        nxt: each candidate's predicted successor state index (the add-delete rule).
        pred_lo: ``pred_lo[s] .. pred_lo[s + 1]`` index the states predicted to lead to ``s``.
        pred: those predecessors, grouped by successor (ascending within a group).

    """

    lo: np.ndarray
    action: np.ndarray
    nxt: np.ndarray
    pred_lo: np.ndarray
    pred: np.ndarray


@functools.cache
def world_model(n: int) -> ModelArrays:
    """The R-classifiers' answers for every state, from the world model's one transition table (cached per n)."""
    table = WorldModel.for_blocks(n).table
    legal = table.legal
    lo = np.zeros(len(legal) + 1, np.int64)
    lo[1:] = np.cumsum([len(row) for row in legal])
    action = np.fromiter((a for row in legal for a in row), np.int64, count=int(lo[-1]))
    source = np.repeat(np.arange(len(legal)), np.diff(lo))
    nxt = table.next_state[source, action].astype(np.int64)
    pred = source[np.argsort(nxt, kind="stable")]
    pred_lo = np.zeros(len(legal) + 1, np.int64)
    pred_lo[1:] = np.cumsum(np.bincount(nxt, minlength=len(legal)))
    for x in (lo, action, nxt, pred_lo, pred):
        x.flags.writeable = False
    return ModelArrays(lo, action, nxt, pred_lo, pred)


class FastCSQL(Learner):
    """CS-QL on arrays, behind the :class:`~csql_sim.learners.paper.learner.Learner` contract.

    Args:
        n: number of blocks (2..6).
        params: CS-QL parameters.
        rng: the only source of randomness.
        goals: the goal states to learn, ascending (None: every state, the paper's one
            engine); a subset makes the engine one shard (:mod:`csql_sim.learners.training.shards`):
            its random tasks draw a goal among ``goals``, and it has no test task.
        ordered: sweep each goal's starts backwards from the goal through the
            R-classifiers' predicted predecessors (backward breadth-first order) instead of
            in index order.
        model: the R-classifiers' answers (:func:`world_model` of n when None), e.g. as a
            worker was sent them.

    Attributes:
        model: the R-classifiers' answers for every state (:func:`world_model`).
        kernel: the state and constants the compiled kernels take
            (:class:`~csql_sim.learners.engines.fast_kernels.Engine`).

    """

    method = "cs-ql"
    engine = "fast"
    params: CSQLParams

    def __init__(self, n: int, params: CSQLParams, rng: np.random.Generator, goals: np.ndarray | None = None,
                 ordered: bool = False, model: ModelArrays | None = None) -> None:
        if n > MAX_FAST_BLOCKS:
            raise CsqlError(f"the fast engine handles up to {MAX_FAST_BLOCKS} blocks; use --engine reference")
        super().__init__(n, params)
        self.rng = rng
        self.model = m = world_model(n) if model is None else model
        count = self.count = len(self.world.states)
        self.sharded = goals is not None
        goals = np.arange(count, dtype=np.int64) if goals is None else np.asarray(goals, np.int64)
        width = len(goals)
        if width == 0 or (np.diff(goals) <= 0).any() or goals[0] < 0 or goals[-1] >= count:
            raise CsqlError(f"goals must be distinct ascending state indices below {count}")
        goal_slot = np.full(count, -1, np.int64)
        goal_slot[goals] = np.arange(width)
        slots, nodes = width * int(m.lo[-1]), width * count
        ctr = np.zeros(fk.CTR_SIZE, np.int64)
        ctr[fk.POS] = BATCH  # spent: the first uniform draws a batch
        self.kernel = fk.Engine(
            buf=np.zeros(BATCH), ctr=ctr, count=count, lo_legal=m.lo, nxt_state=m.nxt,
            node_id=np.full(nodes, -1, np.int64), node_off=np.zeros(nodes, np.int64),
            node_state=np.zeros(nodes, np.int64), node_born=np.zeros(nodes, np.int64),
            q=np.zeros(slots), err=np.zeros(slots), last=np.zeros(slots, np.int64),
            q0=params.q0, gamma=params.gamma, eta=params.eta, payoff=params.payoff, compensated=COMPENSATED_SUM,
            scratch=np.zeros(int(np.diff(m.lo).max())), goals=goals, goal_slot=goal_slot,
            pred_lo=m.pred_lo, pred=m.pred, order=np.zeros(count, np.int64), ordered=ordered,
            seen=np.zeros(int(m.lo[-1]), np.bool_),
        )
        ctr[fk.RECORD] = 1  # trials record the slots they take; the sweep does not
        self.experienced_steps = 0

    @property
    def t(self) -> int:
        """The clock: steps taken over the engine's life."""
        return int(self.kernel.ctr[fk.T])

    # -- training ------------------------------------------------------------------------
    def train(self, trials: int, on_trial: Callable[[int], None] | None = None,
              test_every: int = TEST_EVERY) -> Curve:
        """:meth:`Learner.train`, compiled (``run_training``).

        The compiled loop pauses every 1% of the trials for ``on_trial``, and after every
        :data:`STEPS_PER_CALL` steps in any case: back in Python between calls, a Ctrl-C
        (KeyboardInterrupt) is raised within a fraction of a second. Pauses change nothing
        in the trajectory.
        """
        p = self.params
        points = trials // test_every + 1 if test_every else 0
        steps, values = np.zeros(points, np.int64), np.zeros(points)
        if self.sharded and test_every:
            raise CsqlError("a shard of goals has no test task: train it with test_every=0")
        task = self.test_indices() if test_every else (0, 0)  # the test task costs a BFS per state at 6 blocks
        plan = fk.Schedule(trials, test_every, *task, p.t0, p.t_decay, p.t_min, p.step_cap)
        ctr = self.kernel.ctr
        ctr[fk.K] = ctr[fk.PHASE] = 0
        began = self.t
        try:
            self._run(plan, trials, on_trial, steps, values)
        finally:
            self.experienced_steps += self.t - began
        marks = tuple(range(0, trials + 1, test_every)) if test_every else ()
        return Curve(marks, tuple(int(x) for x in steps), tuple(float(x) for x in values))

    def _run(self, plan: Any, trials: int, on_trial: Callable[[int], None] | None, steps: np.ndarray,
             values: np.ndarray) -> None:
        """The compiled trials of :meth:`train`, in calls of at most :data:`STEPS_PER_CALL` steps."""
        ctr = self.kernel.ctr
        chunk = max(1, trials // 100) if on_trial is not None else trials + 1
        stop, reported = min(chunk, trials), 0
        while True:
            budget = int(ctr[fk.T]) + STEPS_PER_CALL
            status = call_kernel(fk.run_trials, plan, stop, budget, self.rng, self.kernel, steps, values)
            done = int(ctr[fk.K])
            if on_trial is not None:
                for k in range(reported, min(done, trials)):
                    on_trial(k)
            reported = done
            if status == fk.DONE:
                break
            if done >= stop:  # paused for on_trial (not for the step budget)
                stop = min(stop + chunk, trials)

    def run_trial(self, start: int, goal: int, temperature: float, cap: int | None = None) -> int:
        """One trial; returns its steps."""
        cap = self.params.step_cap if cap is None else cap
        steps, _, _ = call_kernel(fk.trial, start, goal, temperature, cap, True, 0.0, self.rng, self.kernel)
        return int(steps)

    @property
    def max_sweep_passes(self) -> int:
        """:attr:`CSQL.max_sweep_passes <csql_sim.learners.paper.cs_ql.CSQL.max_sweep_passes>`."""
        p = self.params
        return p.sweep_passes + p.sweep_greedy_tail if p.sweep else 0

    def sweep(self, on_pass: Callable[[], None] | None = None) -> int:
        """:meth:`CSQL.sweep <csql_sim.learners.paper.cs_ql.CSQL.sweep>`: plan, then the test task once greedily."""
        if not self.params.sweep:
            return 0
        self.kernel.ctr[fk.RECORD] = 0
        try:
            steps = self.plan(on_pass)
            if not self.sharded:  # a shard has no test task
                self.run_trial(*self.test_indices(), 0.0)
        finally:
            self.kernel.ctr[fk.RECORD] = 1
        return steps

    @property
    def backups(self) -> int:
        """Eq. 1-2 updates made by trials and the sweep."""
        return int(self.kernel.ctr[fk.BACKUPS])

    def experience_report(self) -> dict:
        """``experienced_pairs`` (distinct (state, action) pairs trials took) and ``legal_pairs``."""
        return {"experienced_pairs": int(self.kernel.seen.sum()), "legal_pairs": int(self.model.lo[-1]),
                "experienced_steps": self.experienced_steps, "replay_backups": 0}

    def plan(self, on_pass: Callable[[], None] | None = None) -> int:
        """:meth:`CSQL.plan <csql_sim.learners.paper.cs_ql.CSQL.plan>`: greedy passes until |epsilon| <= tolerance.

        Args:
            on_pass: called after each pass (progress).
        """
        p, k = self.params, self.kernel
        before = self.t
        for _ in range(p.sweep_passes):
            start_t = self.t
            self._sweep_pass(p.sweep_eta if p.sweep_backup_all else 0.0)
            if on_pass is not None:
                on_pass()
            used = int(k.ctr[fk.CLS])
            active = k.last[:used] >= start_t
            worst = float(k.err[:used][active].max()) if active.any() else 0.0
            if worst <= p.sweep_tolerance:
                break
        for _ in range(p.sweep_greedy_tail):
            self._sweep_pass(0.0)
            if on_pass is not None:
                on_pass()
        return self.t - before

    def _sweep_pass(self, plan_eta: float) -> None:
        """One pass of the sweep, compiled, in calls of at most :data:`STEPS_PER_CALL` steps (Ctrl-C between).

        A goal's trials take at most ``count ** 2`` steps (``count`` trials capped at ``count`` steps).
        """
        count, width = self.count, len(self.kernel.goals)
        goals = max(1, STEPS_PER_CALL // (count * count))
        for g in range(0, width, goals):
            call_kernel(fk.sweep_pass, plan_eta, self.rng, self.kernel, g, min(g + goals, width))

    # -- export ------------------------------------------------------------------------
    def q_arrays(self) -> dict[str, np.ndarray]:
        """The Q-classifiers settled to now, in creation order: node, action and the fields."""
        k = self.kernel
        used_nodes, used = int(k.ctr[fk.NODES]), int(k.ctr[fk.CLS])
        node_of = np.repeat(np.arange(used_nodes), np.diff(np.append(k.node_off[:used_nodes], used)))
        state = k.node_state[:used_nodes][node_of]
        rank = np.arange(used) - k.node_off[:used_nodes][node_of]
        action = self.model.action[self.model.lo[state] + rank]
        goal = self._goals(used_nodes)[node_of]
        t = self.t
        error = k.err[:used] + self.params.error_increment * (t - k.last[:used])
        born = k.node_born[:used_nodes][node_of]
        age = (t - born) / self.params.age_unit
        return {
            "born": born,
            "state": state,
            "goal": goal,
            "action": action,
            "q": k.q[:used].copy(),
            "error": error,
            "strength": 1.0 - error,
            "age": age,
        }

    def _goals(self, used_nodes: int) -> np.ndarray:
        node_id, targets = self.kernel.node_id, self.kernel.goals
        keys = np.flatnonzero(node_id >= 0)
        goals = np.empty(used_nodes, np.int64)
        goals[node_id[keys]] = targets[keys % len(targets)]
        return goals

    def greedy_table(self) -> GreedyTable:
        """The greedy policy straight from the arrays (the highest Q per node, the first on ties)."""
        a = self.q_arrays()
        count = self.count
        return GreedyTable(self.n, greedy_argmax(a["state"] * count + a["goal"], a["q"], a["action"], count * count))

    def rule_arrays(self) -> dict[str, np.ndarray]:
        """The whole classifier list as the npz form's arrays (R, then Q in creation order)."""
        a = self.q_arrays()
        n, width = self.n, layout(self.n).length
        r = list(r_classifiers(n))
        bodies = np.array([format_state_message(s, 0)[: layout(n).goal_start] for s in self.world.states])
        codes = np.array([goal_code(g, n) for g in range(self.count)])
        conditions = np.char.add(bodies[a["state"]], codes[a["goal"]]).astype(f"S{width}")
        actions = np.array([format_action_message(x, n) for x in self.world.actions], dtype=f"S{width}")
        zeros = np.zeros(len(r))
        return {
            "kind": np.concatenate((np.full(len(r), b"R", "S1"), np.full(len(conditions), b"Q", "S1"))),
            "condition": np.concatenate((np.array([c.condition for c in r], f"S{width}"), conditions)),
            "action": np.concatenate((np.array([c.action for c in r], f"S{width}"), actions[a["action"]])),
            **{name: np.concatenate((zeros, a[name])) for name in ("q", "strength", "age", "error")},
        }

    def counts(self) -> tuple[int, int]:
        """The numbers of R- and Q-classifiers."""
        return len(r_classifiers(self.n)), int(self.kernel.ctr[fk.CLS])

    def file_bytes(self, path: str | os.PathLike, meta: dict) -> str | bytes:
        """The rule file's content for ``path``: npz straight from the arrays, YAML via :meth:`rulebase`."""
        if not is_npz(path):
            return dumps(self.rulebase(meta))
        return arrays_to_bytes(self.n, meta, self.rule_arrays())

    def rulebase(self, meta: dict | None = None) -> RuleBase:
        """The whole classifier list (R, then Q in creation order), as the reference writes it."""
        a = self.q_arrays()
        states, n = self.world.states, self.n
        action_messages = [format_action_message(x, n) for x in self.world.actions]
        messages: dict[tuple[int, int], str] = {}
        out: list = list(r_classifiers(n))
        t = self.t
        rows = zip(a["state"].tolist(), a["goal"].tolist(), a["action"].tolist(), a["q"].tolist(),
                   a["error"].tolist(), a["strength"].tolist(), a["age"].tolist(), a["born"].tolist(), strict=True)
        for s, g, act, q, err, strength, age, born in rows:
            cond = messages.get((s, g))
            if cond is None:
                cond = messages[(s, g)] = format_state_message(states[s], g)
            out.append(QClassifier(cond, action_messages[act], q, strength, age, err, t, born))
        return RuleBase(blocks=n, classifiers=out, meta=dict(meta or {}))
