"""The array-backed LT-QL engine: the reference engine's trajectory, compiled.

:class:`FastTabularQ` is one more engine behind the
:class:`~csql_sim.learners.paper.learner.Learner` contract. It trains exactly as
:class:`csql_sim.learners.paper.lt_ql.TabularQ` does (same uniforms consumed in the same order,
same floating-point operations in the same order, same rows created at the same steps),
so the same seed writes the same rule file byte for byte. Its table is a few numpy arrays
(see :mod:`csql_sim.learners.engines.lt_kernels`) instead of row objects, and its loops are
compiled with numba.

The table is LT-QL's: one row per (state, goal) pair seen, one entry per action of the
world (legal or not), the true transition table as the environment. Rows are allocated as
they are first seen, in arrays that grow (doubling) as needed, never for all pairs at once:
at n = 5 a row is 50 entries of 24 bytes, 1.2 kB, and every pair seen would be 0.9 GB.
"""

from __future__ import annotations

import os
from collections.abc import Callable

import numpy as np

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.files.rulebase import RuleBase, dumps, is_npz
from csql_sim.core.files.rulebase_npz import arrays_to_bytes
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.core.state.message import format_action_message, format_state_message, goal_code, layout
from csql_sim.infra.errors import CsqlError
from csql_sim.learners.engines.fast_engine import COMPENSATED_SUM, call_kernel, fk
from csql_sim.learners.paper.learner import BATCH, TEST_EVERY, Curve, Learner
from csql_sim.learners.paper.params import TabularParams


class _Kernels:
    """The compiled kernels, imported on first use: importing numba costs most of a second."""

    def __getattr__(self, name: str):
        from csql_sim.learners.engines import lt_kernels

        return getattr(lt_kernels, name)


lk = _Kernels()
MAX_LT_FAST_BLOCKS = 5
"""Largest n this engine takes (n = 6 would need up to 86 GB for its table)."""
STEPS_PER_CALL = 50_000
"""Steps one compiled call of :meth:`FastTabularQ.train` may take before it returns to
Python (it pauses between trials, so plus the one under way): some 35 ms at n = 5, where
it takes 1.4 million steps a second."""
ENTRY_ARRAYS = ("q", "err", "last")
ROW_ARRAYS = ("row_state", "row_goal", "row_born", *ENTRY_ARRAYS)
INITIAL_ROWS = 4096
"""Rows allocated up front (fewer when the world has fewer pairs); the arrays double as needed."""


class FastTabularQ(Learner):
    """LT-QL on arrays, behind the :class:`~csql_sim.learners.paper.learner.Learner` contract.

    Args:
        n: number of blocks (2..5).
        params: LT-QL parameters.
        rng: the only source of randomness.

    Attributes:
        count: the number of states.
        actions: the number of actions of the world (entries per row).
        kernel: the state and constants the compiled kernels take
            (:class:`~csql_sim.learners.engines.lt_kernels.Engine`).

    """

    method = "lt-ql"
    engine = "fast"
    params: TabularParams

    def __init__(self, n: int, params: TabularParams, rng: np.random.Generator) -> None:
        if n > MAX_LT_FAST_BLOCKS:
            raise CsqlError(f"LT-QL's fast engine handles up to {MAX_LT_FAST_BLOCKS} blocks; use --engine reference")
        super().__init__(n, params)
        self.rng = rng
        count = self.count = len(self.world.states)
        actions = self.actions = len(self.world.actions)
        table = np.array(self.world.next_state, np.int64).reshape(count, actions)
        nxt = np.where(table >= 0, table, np.arange(count)[:, None]).ravel()  # illegal: unchanged (TableModel)
        nxt.flags.writeable = False
        ctr = np.zeros(lk.CTR_SIZE, np.int64)
        ctr[lk.POS] = BATCH  # spent: the first uniform draws a batch
        rows = min(INITIAL_ROWS, count * (count - 1))
        self.kernel = lk.Engine(
            buf=np.zeros(BATCH), ctr=ctr, count=count, actions=actions, nxt_state=nxt,
            row_id=np.full(count * count, -1, np.int64), row_state=np.zeros(rows, np.int64),
            row_goal=np.zeros(rows, np.int64), row_born=np.zeros(rows, np.int64),
            q=np.zeros(rows * actions), err=np.zeros(rows * actions), last=np.zeros(rows * actions, np.int64),
            max_rows=count * (count - 1), q0=params.q0, gamma=params.gamma, eta=params.eta, payoff=params.payoff,
            compensated=COMPENSATED_SUM, scratch=np.zeros(actions),
        )

    @property
    def t(self) -> int:
        """The clock: steps taken over the engine's life."""
        return int(self.kernel.ctr[lk.T])

    @property
    def rows(self) -> int:
        """The rows (state, goal pairs) seen so far."""
        return int(self.kernel.ctr[lk.ROWS])

    @property
    def capacity(self) -> int:
        """The rows the arrays hold now."""
        return len(self.kernel.row_state)

    # -- training ------------------------------------------------------------------------
    def train(self, trials: int, on_trial: Callable[[int], None] | None = None,
              test_every: int = TEST_EVERY) -> Curve:
        """:meth:`Learner.train`, compiled (``run_training``).

        The compiled loop pauses every 1% of the trials for ``on_trial``, after every
        :data:`STEPS_PER_CALL` steps in any case (back in Python between calls, a Ctrl-C is
        raised within a fraction of a second), and when the table needs room. Pauses
        change nothing in the trajectory.
        """
        p = self.params
        points = trials // test_every + 1 if test_every else 0
        steps, values = np.zeros(points, np.int64), np.zeros(points)
        plan = fk.Schedule(trials, test_every, *self.test_indices(), p.t0, p.t_decay, p.t_min, p.step_cap)
        ctr = self.kernel.ctr
        ctr[lk.K] = ctr[lk.PHASE] = 0
        chunk = max(1, trials // 100) if on_trial is not None else trials + 1
        stop, reported = min(chunk, trials), 0
        while True:
            budget = int(ctr[lk.T]) + STEPS_PER_CALL
            status = call_kernel(lk.run_trials, plan, stop, budget, self.rng, self.kernel, steps, values)
            done = int(ctr[lk.K])
            if on_trial is not None:
                for k in range(reported, min(done, trials)):
                    on_trial(k)
            reported = done
            if status == lk.DONE:
                break
            if status == lk.FULL:
                self._grow(p.step_cap)
            elif done >= stop:  # paused for on_trial (not for the step budget)
                stop = min(stop + chunk, trials)
        marks = tuple(range(0, trials + 1, test_every)) if test_every else ()
        return Curve(marks, tuple(int(x) for x in steps), tuple(float(x) for x in values))

    def _grow(self, cap: int) -> None:
        """Room for a trial of ``cap`` steps: double the row arrays (at least), up to every pair.

        The arrays are resized in place (``ndarray.resize``: realloc, which moves a large
        block's pages rather than copying them), so growing holds no second copy.
        """
        k = self.kernel
        rows = min(k.max_rows, max(2 * self.capacity, self.rows + min(cap, k.max_rows) + 1))
        arrays = {name: getattr(k, name) for name in ROW_ARRAYS}
        self.kernel = k = k._replace(**dict.fromkeys(ROW_ARRAYS))
        for name in ROW_ARRAYS:
            x = arrays.pop(name)  # its one reference: numpy refuses to resize an array referenced elsewhere
            x.resize(rows * (self.actions if name in ENTRY_ARRAYS else 1))
            arrays[name] = x
        self.kernel = k._replace(**arrays)

    # -- what was learned ----------------------------------------------------------------
    def _order(self) -> np.ndarray:
        """The used rows sorted by (goal, state), the reference's rule-base order."""
        k, used = self.kernel, self.rows
        return np.lexsort((k.row_state[:used], k.row_goal[:used]))

    def entry_arrays(self) -> dict[str, np.ndarray]:
        """Every entry settled to now, in rule-base order (A per row).

        Per row (``state``, ``goal``, ``born``, ``age``) and per entry (``q``, ``error``,
        ``strength``); an entry's action is its place in its row.
        """
        k, a, t, p, used = self.kernel, self.actions, self.t, self.params, self.rows
        order = self._order()

        def entries(x: np.ndarray) -> np.ndarray:
            return x[: used * a].reshape(used, a)[order].ravel()

        error = entries(k.err) + p.error_increment * (t - entries(k.last))
        born = k.row_born[order]
        return {"state": k.row_state[order], "goal": k.row_goal[order], "born": born,
                "age": (t - born) / p.age_unit, "q": entries(k.q), "error": error, "strength": 1.0 - error}

    def greedy_table(self) -> GreedyTable:
        """The greedy action of every row seen (the first largest Q), straight from the arrays."""
        k, used, count = self.kernel, self.rows, self.count
        best = np.full(count * count, -1, np.int8)
        q = k.q[: used * self.actions].reshape(used, self.actions)
        if used:
            best[k.row_state[:used] * count + k.row_goal[:used]] = np.argmax(q, axis=1)
        return GreedyTable(self.n, best)

    def counts(self) -> tuple[int, int]:
        """No R-classifiers; one Q-classifier per action of every row seen."""
        return 0, self.rows * self.actions

    def rule_arrays(self) -> dict[str, np.ndarray]:
        """The classifier list as the npz form's arrays (Q-classifiers only, rule-base order)."""
        a = self.entry_arrays()
        n, width, count = self.n, layout(self.n).length, len(a["state"])
        bodies = np.array([format_state_message(s, 0)[: layout(n).goal_start] for s in self.world.states])
        codes = np.array([goal_code(g, n) for g in range(self.count)])
        rows = np.char.add(bodies[a["state"]], codes[a["goal"]]).astype(f"S{width}")
        actions = np.array([format_action_message(x, n) for x in self.world.actions], dtype=f"S{width}")
        return {
            "kind": np.full(count * self.actions, b"Q", "S1"),
            "condition": np.repeat(rows, self.actions),
            "action": np.tile(actions, count),
            "age": np.repeat(a["age"], self.actions),
            **{name: a[name] for name in ("q", "strength", "error")},
        }

    def file_bytes(self, path: str | os.PathLike, meta: dict) -> str | bytes:
        """The rule file's content for ``path``: npz straight from the arrays, YAML via :meth:`rulebase`."""
        if not is_npz(path):
            return dumps(self.rulebase(meta))
        return arrays_to_bytes(self.n, meta, self.rule_arrays())

    def rulebase(self, meta: dict | None = None) -> RuleBase:
        """The table as Q-classifiers, as :meth:`~csql_sim.learners.paper.lt_ql.TabularQ.rulebase`."""
        a = self.entry_arrays()
        states, n, t, per_row = self.world.states, self.n, self.t, self.actions
        actions = [format_action_message(x, n) for x in self.world.actions]
        q, strength, error = a["q"].tolist(), a["strength"].tolist(), a["error"].tolist()
        out: list = []
        rows = zip(a["state"].tolist(), a["goal"].tolist(), a["age"].tolist(), a["born"].tolist(), strict=True)
        for j, (s, g, age, born) in enumerate(rows):
            message = format_state_message(states[s], g)
            out.extend(QClassifier(message, action, q[e], strength[e], age, error[e], t, born)
                       for e, action in enumerate(actions, j * per_row))
        return RuleBase(blocks=n, classifiers=out, meta=dict(meta or {}))
