"""The array-backed CS-QL engine: the reference engine's trajectory, compiled.

:class:`FastCSQL` trains exactly as :class:`csql_sim.learners.csql.CSQL` does (same
uniforms consumed in the same order, same floating-point operations in the same order,
same classifier creation order), so the same seed writes the same rule file byte for
byte. Its state is a handful of numpy arrays (see :mod:`csql_sim.learners.fast_kernels`)
instead of classifier objects, and its loops are compiled with numba.

The domain knowledge is the same: the candidates of a state and their predicted
successors are read off the R-classifiers (the precondition rules matched and the
add-delete rule applied by :class:`~csql_sim.core.world_model.WorldModel`), once per
state, when the engine is built. Nothing comes from the world's own transition table.
"""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from csql_sim.core.message import decode_code, format_action_message, format_state_message, goal_code, layout
from csql_sim.core.q_classifier import QClassifier
from csql_sim.core.r_classifier import r_classifiers
from csql_sim.core.rulebase import RuleBase, dumps, is_npz
from csql_sim.core.rulebase_npz import arrays_to_bytes
from csql_sim.core.task import test_task
from csql_sim.core.world import BlocksWorld
from csql_sim.core.world_model import WorldModel
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import write_atomic
from csql_sim.learners.learner import BATCH
from csql_sim.learners.params import CSQLParams
from csql_sim.learners.trial import TEST_EVERY, Curve


class _Kernels:
    """The compiled kernels, imported on first use: importing numba costs most of a second."""

    def __getattr__(self, name: str):
        from csql_sim.learners import fast_kernels

        return getattr(fast_kernels, name)


fk = _Kernels()
MAX_FAST_BLOCKS = 5
COMPENSATED_SUM = sys.version_info >= (3, 12)
"""Python 3.12 made ``sum()`` of floats compensated; the kernels follow the running Python."""


@dataclass(frozen=True)
class ModelArrays:
    """The R-classifiers' answers for every state, as arrays.

    Attributes:
        lo: ``lo[s] .. lo[s + 1]`` index state ``s``'s candidates in ``action`` and ``nxt``.
        action: each candidate's action index (the precondition rules' order).
        nxt: each candidate's predicted successor state index (the add-delete rule).

    """

    lo: np.ndarray
    action: np.ndarray
    nxt: np.ndarray


@functools.cache
def world_model(n: int) -> ModelArrays:
    """Match and predict every state message once through the R-classifiers (cached per n)."""
    world = BlocksWorld.of(n)
    model = WorldModel.for_blocks(n)
    lay = layout(n)
    width, body_end = lay.action_width, lay.goal_start
    body_index = {format_state_message(s, 0)[:body_end]: i for i, s in enumerate(world.states)}
    lo, actions, nxt = [0], [], []
    for s in world.states:
        message = format_state_message(s, 0)
        for action in model.legal_actions(message):
            actions.append(decode_code(action[1 : 1 + width]) - 1)
            nxt.append(body_index[model.predict(message, action)[:body_end]])
        lo.append(len(actions))
    arrays = [np.array(x, np.int64) for x in (lo, actions, nxt)]
    for a in arrays:
        a.flags.writeable = False
    return ModelArrays(*arrays)


class FastCSQL:
    """CS-QL on arrays; the same public steps as the reference: run, sweep, run_trial, rulebase.

    Args:
        n: number of blocks (2..5).
        params: CS-QL parameters.
        rng: the only source of randomness.

    """

    method = "cs-ql"

    def __init__(self, n: int, params: CSQLParams, rng: np.random.Generator) -> None:
        if n > MAX_FAST_BLOCKS:
            raise CsqlError(f"the fast engine handles up to {MAX_FAST_BLOCKS} blocks; use --engine reference")
        self.n, self.params, self.rng = n, params, rng
        self.world = BlocksWorld.of(n)
        self.model = world_model(n)
        count = self.count = len(self.world.states)
        slots = count * int(self.model.lo[-1])
        self.node_id = np.full(count * count, -1, np.int64)
        self.node_off = np.zeros(count * count, np.int64)
        self.node_state = np.zeros(count * count, np.int64)
        self.node_born = np.zeros(count * count, np.int64)
        self.q = np.zeros(slots)
        self.err = np.zeros(slots)
        self.last = np.zeros(slots, np.int64)
        self.ctr = np.zeros(fk.CTR_SIZE, np.int64)
        self.buf = np.zeros(BATCH)
        self.ctr[fk.POS] = BATCH  # spent: the first uniform draws a batch
        self.scratch = np.zeros(int(np.diff(self.model.lo).max()))

    @property
    def t(self) -> int:
        """The clock: steps taken over the engine's life."""
        return int(self.ctr[fk.T])

    def _state(self) -> tuple:
        p = self.params
        return (
            self.rng,
            self.buf,
            self.ctr,
            self.count,
            self.model.lo,
            self.model.nxt,
            self.node_id,
            self.node_off,
            self.node_state,
            self.node_born,
            self.q,
            self.err,
            self.last,
            p.q0,
            p.gamma,
            p.eta,
            p.payoff,
            COMPENSATED_SUM,
            self.scratch,
        )

    def test_task(self) -> tuple[int, int]:
        """The test task's (start, goal) state indices (:func:`csql_sim.core.task.test_task`)."""
        task = test_task(self.n)
        return self.world.state_index(task.start), self.world.state_index(task.goal)

    def run(self, trials: int, test_every: int = TEST_EVERY, on_trial: Callable[[int], None] | None = None) -> Curve:
        """``Learner.run``: ``trials`` random tasks, the test task every ``test_every``."""
        p = self.params
        points = trials // test_every + 1 if test_every else 0
        steps, values = np.zeros(points, np.int64), np.zeros(points)
        start, goal = self.test_task()
        self.ctr[fk.K] = self.ctr[fk.PHASE] = 0
        chunk = max(1, trials // 100) if on_trial is not None else trials + 1
        stop, reported = min(chunk, trials), 0
        while True:
            status = fk.run_trials(
                trials,
                stop,
                test_every,
                start,
                goal,
                p.t0,
                p.t_decay,
                p.t_min,
                p.step_cap,
                *self._state(),
                steps,
                values,
            )
            done = int(self.ctr[fk.K])
            if on_trial is not None:
                for k in range(reported, min(done, trials)):
                    on_trial(k)
            reported = done
            if status == fk.DONE:
                break
            stop = min(stop + chunk, trials)
        marks = tuple(range(0, trials + 1, test_every)) if test_every else ()
        return Curve(marks, tuple(int(x) for x in steps), tuple(float(x) for x in values))

    def run_trial(self, start: int, goal: int, temperature: float, cap: int | None = None) -> int:
        """One trial; returns its steps."""
        cap = self.params.step_cap if cap is None else cap
        steps, _, _ = fk.trial(start, goal, temperature, cap, True, 0.0, *self._state())
        return int(steps)

    def sweep(self, on_pass: Callable[[], None] | None = None) -> int:
        """:meth:`CSQL.sweep`: greedy passes over every pair until |epsilon| <= tolerance.

        Args:
            on_pass: called after each pass (progress).
        """
        p = self.params
        before = self.t
        for _ in range(p.sweep_passes):
            start_t = self.t
            fk.sweep_pass(p.sweep_eta if p.sweep_backup_all else 0.0, *self._state())
            if on_pass is not None:
                on_pass()
            used = int(self.ctr[fk.CLS])
            active = self.last[:used] >= start_t
            worst = float(self.err[:used][active].max()) if active.any() else 0.0
            if worst <= p.sweep_tolerance:
                break
        for _ in range(p.sweep_greedy_tail):
            fk.sweep_pass(0.0, *self._state())
            if on_pass is not None:
                on_pass()
        return self.t - before

    # -- export ------------------------------------------------------------------------
    def q_arrays(self) -> dict[str, np.ndarray]:
        """The Q-classifiers settled to now, in creation order: node, action and the fields."""
        used_nodes, used = int(self.ctr[fk.NODES]), int(self.ctr[fk.CLS])
        node_of = np.repeat(np.arange(used_nodes), np.diff(np.append(self.node_off[:used_nodes], used)))
        state = self.node_state[:used_nodes][node_of]
        rank = np.arange(used) - self.node_off[:used_nodes][node_of]
        action = self.model.action[self.model.lo[state] + rank]
        goal = self._goals(used_nodes)[node_of]
        t = self.t
        error = self.err[:used] + self.params.error_increment * (t - self.last[:used])
        born = self.node_born[:used_nodes][node_of]
        age = (t - born) / self.params.age_unit
        return {
            "born": born,
            "state": state,
            "goal": goal,
            "action": action,
            "q": self.q[:used].copy(),
            "error": error,
            "strength": 1.0 - error,
            "age": age,
        }

    def _goals(self, used_nodes: int) -> np.ndarray:
        keys = np.flatnonzero(self.node_id >= 0)
        goals = np.empty(used_nodes, np.int64)
        goals[self.node_id[keys]] = keys % self.count
        return goals

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
        return len(r_classifiers(self.n)), int(self.ctr[fk.CLS])

    def file_bytes(self, path, meta: dict) -> str | bytes:
        """The rule file's content for ``path``: npz straight from the arrays, YAML via :meth:`rulebase`."""
        if not is_npz(path):
            return dumps(self.rulebase(meta))
        return arrays_to_bytes(self.n, meta, self.rule_arrays())

    def save(self, path, meta: dict) -> Path:
        """Write the rule file atomically (npz or YAML by suffix)."""
        return write_atomic(path, self.file_bytes(path, meta))

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
