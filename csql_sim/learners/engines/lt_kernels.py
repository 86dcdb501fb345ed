"""Compiled inner loops of LT-QL's array engine (:mod:`csql_sim.learners.engines.lt_fast`).

Every function mirrors one piece of the reference engine (:mod:`csql_sim.learners.paper.lt_ql`,
:mod:`csql_sim.learners.paper.trial`, :mod:`csql_sim.learners.paper.selection`) operation for
operation, so that the same uniforms give the same floating-point results:

* :func:`trial` is :func:`~csql_sim.learners.paper.trial.run_trial` with LT-QL's ``act``
  (eq. 3 over all actions of the world, exactly as
  :func:`~csql_sim.learners.paper.selection.boltzmann` computes it: the first largest value,
  ``exp((v - top) / T)``, the weights summed as Python's ``sum`` does, the cumulative
  draw), the true transition table (an illegal action leaves the state unchanged) and
  ``learn`` (eq. 1, 2);
* :func:`run_trials` is :func:`~csql_sim.learners.paper.trial.run_training`.

As in :mod:`csql_sim.learners.engines.fast_kernels`, the kernels take the engine's arrays and
constants as one record, :class:`Engine`, with the generator beside it, and the trial
loop is written out in one function (numba's inlining of small helpers costs
reference-count traffic on every step).

Memory layout. A *row* is a (state, goal) pair that has been seen; rows are numbered in
the order the reference creates them, and row ``j``'s table entries (one per action of
the world) are ``q[j * A .. j * A + A]`` (likewise ``err`` and ``last``). The row arrays
hold ``capacity`` rows; :func:`run_trials` returns :data:`FULL` before a trial that could
run out of room (a trial creates at most ``cap + 1`` rows), and the caller grows them.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from csql_sim.learners.engines.fast_kernels import weighted_draw

ROWS, T, POS, K, PHASE = range(5)
"""Indices into ``ctr``: rows used, clock, stream position, trial index, phase within a
trial index (0 test task, 1 random task)."""
CTR_SIZE = 5
DONE, PAUSED, FULL = 0, 1, 2


class Engine(NamedTuple):
    """The engine's state and constants, as every kernel takes them.

    Attributes:
        buf: the current batch of uniforms (``rng.random(BATCH)``).
        ctr: the counters (indices :data:`ROWS` .. :data:`PHASE`).
        count: the number of states.
        actions: the number of actions of the world (A).
        nxt_state: ``nxt_state[s * A + a]``, the state after action ``a`` in ``s`` (``s`` if illegal).
        row_id: row of each ``state * count + goal`` (-1: not seen yet).
        row_state: each row's state.
        row_goal: each row's goal.
        row_born: the clock when each row was created.
        q: Q-hat per entry (row-major, A per row).
        err: |epsilon| per entry at its last update.
        last: the clock of each entry's last update.
        max_rows: the most rows there can be (every pair of distinct states).
        q0: a new entry's Q-value.
        gamma: the discount (eq. 2).
        eta: the step size (eq. 1).
        payoff: the reward at the goal.
        compensated: sum weights as Python >= 3.12's compensated ``sum()`` does.
        scratch: room for one row's Boltzmann weights.

    """

    buf: np.ndarray
    ctr: np.ndarray
    count: int
    actions: int
    nxt_state: np.ndarray
    row_id: np.ndarray
    row_state: np.ndarray
    row_goal: np.ndarray
    row_born: np.ndarray
    q: np.ndarray
    err: np.ndarray
    last: np.ndarray
    max_rows: int
    q0: float
    gamma: float
    eta: float
    payoff: float
    compensated: bool
    scratch: np.ndarray


@njit(cache=True, error_model="numpy")
def new_row(e, s, g, t):
    """Create the row of (s, g) on engine ``e`` at clock ``t`` (``TabularQ.row``): every entry q0."""
    ctr = e.ctr
    j = ctr[ROWS]
    ctr[ROWS] = j + 1
    e.row_id[s * e.count + g] = j
    e.row_state[j] = s
    e.row_goal[j] = g
    e.row_born[j] = t
    off = j * e.actions
    for i in range(e.actions):
        e.q[off + i] = e.q0
        e.err[off + i] = 0.0
        e.last[off + i] = t
    return j


@njit(cache=True, error_model="numpy")
def trial(start, goal, temperature, cap, track, rng, e):
    """One trial on engine ``e``: (steps, reached, value_sum); ``track`` sums the chosen entries' Q-values."""
    count, na, gamma, eta, payoff, compensated = e.count, e.actions, e.gamma, e.eta, e.payoff, e.compensated
    t = e.ctr[T]
    pos = e.ctr[POS]
    size = e.buf.shape[0]
    s = start
    j = e.row_id[start * count + goal]
    if j < 0:
        j = new_row(e, start, goal, t)
    value_sum = 0.0
    t0 = t
    end = t0 + cap
    reached = False
    while t < end:
        off = j * na
        if pos >= size:  # the stream's next batch
            e.buf[:] = rng.random(size)
            pos = 0
        u = e.buf[pos]
        pos += 1
        top = e.q[off]  # eq. 3 over all actions
        for k in range(1, na):
            if e.q[off + k] > top:
                top = e.q[off + k]
        i = 0
        if temperature <= 0.0:
            for k in range(na):
                if e.q[off + k] == top:
                    i = k
                    break
        else:
            prev = e.q[off]  # equal values have equal weights (+-0 too: exp(+-0) = 1): exp once per run
            w = math.exp((prev - top) / temperature)
            e.scratch[0] = w
            for k in range(1, na):
                v = e.q[off + k]
                if v != prev:
                    prev = v
                    w = math.exp((v - top) / temperature)
                e.scratch[k] = w
            i = weighted_draw(e.scratch, na, u, compensated)
        c = off + i
        if track:
            value_sum += e.q[c]
        ns = e.nxt_state[s * na + i]
        nj = -1
        target = payoff
        if ns != goal:
            nj = e.row_id[ns * count + goal]
            if nj < 0:
                nj = new_row(e, ns, goal, t)
            noff = nj * na
            best = e.q[noff]
            for d in range(noff + 1, noff + na):
                if e.q[d] > best:
                    best = e.q[d]
            target = gamma * best
        t += 1
        eps = target - e.q[c]  # eq. 1 and 2
        e.q[c] += eta * eps
        e.err[c] = eps if eps >= 0.0 else -eps
        e.last[c] = t
        if nj < 0:
            reached = True
            break
        j = nj
        s = ns
    e.ctr[T] = t
    e.ctr[POS] = pos
    return t - t0, reached, value_sum


@njit(cache=True, error_model="numpy")
def _full(e, cap):
    """Whether a trial of up to ``cap`` steps could need more rows than the arrays hold."""
    capacity = e.row_state.shape[0]
    return capacity < e.max_rows and capacity - e.ctr[ROWS] <= cap


@njit(cache=True, error_model="numpy")
def run_trials(plan, k_stop, t_stop, rng, e, curve_steps, curve_values):
    """``run_training`` of schedule ``plan`` on engine ``e``: the test task every ``plan.test_every`` trials.

    Stops with PAUSED when trial ``k_stop`` is due (for a progress bar) or, between trials,
    once the clock has reached ``t_stop`` (so that the caller sees Ctrl-C); with FULL
    before a trial that might not find room for its rows (the caller grows the arrays);
    DONE after the test task that follows the last trial. A pause changes nothing: the
    next call resumes the same trajectory. Test task ``m`` writes ``curve_steps[m]`` and
    ``curve_values[m]``.
    """
    trials, test_every, cap = plan.trials, plan.test_every, plan.cap
    buf, ctr, count = e.buf, e.ctr, e.count
    size = buf.shape[0]
    while True:
        k = ctr[K]
        temperature = plan.t0 * plan.t_decay ** np.float64(k)  # CommonParams.temperature, operation for operation
        if not temperature > plan.t_min:
            temperature = plan.t_min
        if ctr[PHASE] == 0:
            if (k == k_stop or ctr[T] >= t_stop) and k < trials:
                return PAUSED
            if test_every > 0 and k % test_every == 0:
                if _full(e, cap):
                    return FULL
                steps, _, vsum = trial(plan.test_start, plan.test_goal, temperature, cap, True, rng, e)
                m = k // test_every
                curve_steps[m] = steps
                curve_values[m] = vsum / steps if steps else 0.0
            if k == trials:
                return DONE
            ctr[PHASE] = 1
        if _full(e, cap):
            return FULL
        pos = ctr[POS]  # UniformStream.task: two uniforms, a batch boundary keeping the leftover first
        if pos >= size:
            buf[:] = rng.random(size)
            pos = 0
        u = buf[pos]
        pos += 1
        if pos >= size:
            buf[:] = rng.random(size)
            pos = 0
        v = buf[pos]
        ctr[POS] = pos + 1
        start = min(int(u * count), count - 1)
        goal = min(int(v * (count - 1)), count - 2)
        if goal >= start:
            goal += 1
        trial(start, goal, temperature, cap, False, rng, e)
        ctr[K] = k + 1
        ctr[PHASE] = 0
