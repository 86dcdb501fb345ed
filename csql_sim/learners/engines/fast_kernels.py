"""Compiled inner loops of the array-backed CS-QL engine (:mod:`csql_sim.learners.engines.fast_engine`).

Every function mirrors one piece of the reference engine (:mod:`csql_sim.learners.paper.cs_ql`,
:mod:`csql_sim.learners.paper.trial`, :mod:`csql_sim.learners.paper.selection`) operation for
operation, so that the same uniforms give the same floating-point results:

* :func:`trial` is :func:`~csql_sim.learners.paper.trial.run_trial` with CS-QL's ``act``
  (eq. 3 exactly as :func:`~csql_sim.learners.paper.selection.boltzmann` computes it: the first
  largest value, ``exp((v - top) / T)``, the weights summed as Python's ``sum`` does, the
  cumulative draw), ``learn`` (eq. 1, 2) and, with ``plan_eta > 0``, ``update_all``;
* :func:`run_trials` is :func:`~csql_sim.learners.paper.trial.run_training`;
* :func:`sweep_pass` is (a range of goals of) one pass of :meth:`~csql_sim.learners.paper.cs_ql.CSQL.sweep`.

The kernels take the engine's arrays and constants as one record, :class:`Engine` (a
NamedTuple, which numba passes as a tuple), with the generator ``rng`` beside it (inside
the record it would make numba type the whole record in Python on every call, about
0.1 ms), and :func:`run_trials` takes the training schedule as another, :class:`Schedule`.
The loops index the record's arrays where they use them (``e.q[c]``): numba prunes the
reference counting of each such access, whereas unpacking the arrays into locals at the
top of :func:`trial` cost a reference-count increment and decrement per array per trial
(20-30% slower). The trial loop is written out in one function on purpose: numba's
IR-level inlining of small helpers cost reference-count traffic on every step (about 10x
slower).

Memory layout. A *node* is a (state, goal) pair that has been posted; nodes are numbered
in the order they were first processed, and node ``j``'s Q-classifiers are the
consecutive slots ``off[j] .. off[j] + legal count`` of ``q``, ``err`` and ``last`` (the
candidates in precondition-rule order). That is the reference's classifier-list order.

Counters live in one int64 array ``ctr`` (indices below), so a run can pause (for a
progress bar, or to let Python see Ctrl-C) and resume. The uniform stream is the reference's: ``rng.random(BATCH)``
batches (numba draws from the same ``numpy.random.Generator``, the same numbers), one
uniform per selection, two per random task.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

NODES, CLS, T, POS, K, PHASE, BACKUPS, RECORD = range(8)
"""Indices into ``ctr``: nodes used, classifier slots used, clock, stream position,
trial index, phase within a trial index (0 test task, 1 random task), eq. 1-2 backups
made, and whether trials record the (state, action) slots they take in ``seen`` (1) or not (0)."""
CTR_SIZE = 8
DONE, PAUSED = 0, 1


class Engine(NamedTuple):
    """The engine's state and constants, as every kernel takes them.

    The arrays are updated in place; the scalars are fixed for the engine's life.

    Attributes:
        buf: the current batch of uniforms (``rng.random(BATCH)``).
        ctr: the counters (indices :data:`NODES` .. :data:`PHASE`).
        count: the number of states.
        lo_legal: ``lo_legal[s] .. lo_legal[s + 1]`` index state ``s``'s candidates.
        nxt_state: each candidate's predicted successor state.
        node_id: node of each ``state * len(goals) + goal_slot[goal]`` (-1: not posted yet).
        node_off: each node's first classifier slot.
        node_state: each node's state.
        node_born: the clock when each node was covered.
        q: Q-value per slot.
        err: |epsilon| per slot at its last update.
        last: the clock of each slot's last update.
        q0: a new classifier's Q-value.
        gamma: the discount (eq. 2).
        eta: the step size (eq. 1).
        payoff: the reward at the goal.
        compensated: sum weights as Python >= 3.12's compensated ``sum()`` does.
        scratch: room for one state's Boltzmann weights.
        goals: the goal states this engine learns, ascending (all states: the paper's one
            engine; a subset: one shard of goals, :mod:`csql_sim.learners.training.shards`).
        goal_slot: each state's position in ``goals`` (-1: not one of them); node ``(s, g)``
            is ``node_id[s * len(goals) + goal_slot[g]]``.
        pred_lo: ``pred_lo[s] .. pred_lo[s + 1]`` index the states the R-classifiers predict
            lead to ``s`` in one step (``pred``); used by ordered sweeps only.
        pred: the predecessors, grouped by successor.
        order: room for one sweep order (``count`` states).
        ordered: sweep the starts of a goal backwards from it through ``pred`` (backward
            breadth-first order from the goal) instead of in index order.
        seen: each (state, action) slot a recording trial took (``ctr[RECORD]``).

    """

    buf: np.ndarray
    ctr: np.ndarray
    count: int
    lo_legal: np.ndarray
    nxt_state: np.ndarray
    node_id: np.ndarray
    node_off: np.ndarray
    node_state: np.ndarray
    node_born: np.ndarray
    q: np.ndarray
    err: np.ndarray
    last: np.ndarray
    q0: float
    gamma: float
    eta: float
    payoff: float
    compensated: bool
    scratch: np.ndarray
    goals: np.ndarray
    goal_slot: np.ndarray
    pred_lo: np.ndarray
    pred: np.ndarray
    order: np.ndarray
    ordered: bool
    seen: np.ndarray


class Schedule(NamedTuple):
    """What :func:`run_trials` runs: the trials, the test task and the temperature schedule.

    Attributes:
        trials: random training trials.
        test_every: the test task runs before every this many (0: never).
        test_start: the test task's start state.
        test_goal: the test task's goal state.
        t0: the first temperature.
        t_decay: its decay per trial.
        t_min: its floor.
        cap: the step cap of a trial.

    """

    trials: int
    test_every: int
    test_start: int
    test_goal: int
    t0: float
    t_decay: float
    t_min: float
    cap: int


@njit(cache=True, error_model="numpy")
def weighted_draw(weights, size, u, compensated):
    """The index eq. 3 draws with uniform ``u`` from ``weights[:size]``, as selection.boltzmann does.

    The weights are summed as Python's ``sum`` does (Neumaier-compensated on Python >=
    3.12), then the first index whose cumulative weight exceeds ``u * total`` is taken
    (the last one if rounding leaves none). Shared by CS-QL's and LT-QL's kernels.
    """
    total = weights[0]
    comp = 0.0
    for k in range(1, size):
        x = weights[k]
        sm = total + x
        if compensated:
            if abs(total) >= abs(x):
                comp += (total - sm) + x
            else:
                comp += (x - sm) + total
        total = sm
    if compensated and comp != 0.0 and math.isfinite(comp):
        total += comp
    x = u * total
    acc = 0.0
    for k in range(size):
        acc += weights[k]
        if x < acc:
            return k
    return size - 1


@njit(cache=True, error_model="numpy")
def new_node(e, s, g, t):
    """Process (cover) the node of (s, g) on engine ``e`` at clock ``t``: its Q-classifiers get the next slots."""
    ctr = e.ctr
    j = ctr[NODES]
    ctr[NODES] = j + 1
    e.node_id[s * e.goals.shape[0] + e.goal_slot[g]] = j
    off = ctr[CLS]
    nl = e.lo_legal[s + 1] - e.lo_legal[s]
    ctr[CLS] = off + nl
    e.node_off[j] = off
    e.node_state[j] = s
    e.node_born[j] = t
    for i in range(nl):
        e.q[off + i] = e.q0
        e.err[off + i] = 0.0
        e.last[off + i] = t
    return j


@njit(cache=True, error_model="numpy")
def trial(start, goal, temperature, cap, track, plan_eta, rng, e):
    """One trial on engine ``e``: (steps, reached, value_sum). ``plan_eta > 0``: Dyna backups of every candidate.

    ``track`` sums the chosen classifiers' Q-values (the test task's mean).
    """
    gamma, eta, payoff, compensated = e.gamma, e.eta, e.payoff, e.compensated
    t = e.ctr[T]
    pos = e.ctr[POS]
    size = e.buf.shape[0]
    width, gs = e.goals.shape[0], e.goal_slot[goal]
    j = e.node_id[start * width + gs]
    if j < 0:
        j = new_node(e, start, goal, t)
    value_sum = 0.0
    t0 = t
    end = t0 + cap
    reached = False
    while t < end:
        s = e.node_state[j]
        off = e.node_off[j]
        lo = e.lo_legal[s]
        nl = e.lo_legal[s + 1] - lo
        if pos >= size:  # the stream's next batch
            e.buf[:] = rng.random(size)
            pos = 0
        u = e.buf[pos]
        pos += 1
        i = 0  # eq. 3; a lone candidate is taken without it (the uniform is spent either way)
        if nl > 1:
            top = e.q[off]
            for k in range(1, nl):
                if e.q[off + k] > top:
                    top = e.q[off + k]
            if temperature <= 0.0:
                for k in range(nl):
                    if e.q[off + k] == top:
                        i = k
                        break
            else:
                for k in range(nl):
                    e.scratch[k] = math.exp((e.q[off + k] - top) / temperature)
                i = weighted_draw(e.scratch, nl, u, compensated)
        c = off + i
        if e.ctr[RECORD]:
            e.seen[lo + i] = True
        if track:
            value_sum += e.q[c]
        ns = e.nxt_state[lo + i]
        nj = -1
        target = payoff
        if ns != goal:
            nj = e.node_id[ns * width + gs]
            if nj < 0:
                nj = new_node(e, ns, goal, t)
            noff = e.node_off[nj]
            best = -np.inf
            for d in range(noff, noff + e.lo_legal[ns + 1] - e.lo_legal[ns]):
                if e.q[d] > best:
                    best = e.q[d]
            target = gamma * best
        t += 1
        if plan_eta > 0.0:  # CSQL.update_all: successors in candidate order at t - 1, then every backup
            for k in range(nl):
                ks = e.nxt_state[lo + k]
                if ks != goal and e.node_id[ks * width + gs] < 0:
                    new_node(e, ks, goal, t - 1)
            for k in range(nl):
                ks = e.nxt_state[lo + k]
                kt = payoff
                if ks != goal:
                    koff = e.node_off[e.node_id[ks * width + gs]]
                    best = -np.inf
                    for d in range(koff, koff + e.lo_legal[ks + 1] - e.lo_legal[ks]):
                        if e.q[d] > best:
                            best = e.q[d]
                    kt = gamma * best
                eps = kt - e.q[off + k]
                e.q[off + k] += plan_eta * eps
                e.err[off + k] = eps if eps >= 0.0 else -eps
                e.last[off + k] = t
            e.ctr[BACKUPS] += nl
        else:  # eq. 1 and 2
            e.ctr[BACKUPS] += 1
            eps = target - e.q[c]
            e.q[c] += eta * eps
            e.err[c] = eps if eps >= 0.0 else -eps
            e.last[c] = t
        if nj < 0:
            reached = True
            break
        j = nj
    e.ctr[T] = t
    e.ctr[POS] = pos
    return t - t0, reached, value_sum


@njit(cache=True, error_model="numpy")
def run_trials(plan, k_stop, t_stop, rng, e, curve_steps, curve_values):
    """``run_training`` of schedule ``plan`` on engine ``e``: the test task every ``plan.test_every`` trials.

    Stops with PAUSED when trial ``k_stop`` is due (for a progress bar) or, between trials,
    once the clock has reached ``t_stop`` (so that the caller sees Ctrl-C), DONE after the
    test task that follows the last trial. A pause changes nothing: the next call resumes
    the same trajectory. Test task ``m`` writes ``curve_steps[m]`` and ``curve_values[m]``.
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
                steps, _, vsum = trial(plan.test_start, plan.test_goal, temperature, cap, True, 0.0, rng, e)
                m = k // test_every
                curve_steps[m] = steps
                curve_values[m] = vsum / steps if steps else 0.0
            if k == trials:
                return DONE
            ctr[PHASE] = 1
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
        width = e.goals.shape[0]
        if width == count:  # UniformStream.task
            start = min(int(u * count), count - 1)
            goal = min(int(v * (count - 1)), count - 2)
            if goal >= start:
                goal += 1
        else:  # a shard: one of its goals, then a start among the other states
            goal = e.goals[min(int(u * width), width - 1)]
            start = min(int(v * (count - 1)), count - 2)
            if start >= goal:
                start += 1
        trial(start, goal, temperature, cap, False, 0.0, rng, e)
        ctr[K] = k + 1
        ctr[PHASE] = 0


@njit(cache=True, error_model="numpy")
def sweep_order(e, goal):
    """The starts of ``goal`` backwards from it through the predicted predecessors, breadth-first, in ``e.order``.

    States from which the R-classifiers predict no way to ``goal`` follow in index order.
    Returns the number of starts (``count - 1``: every state but the goal).
    """
    count, order = e.count, e.order
    seen = np.zeros(count, np.bool_)
    seen[goal] = True
    order[0] = goal
    head, tail = 0, 1
    while head < tail:
        x = order[head]
        head += 1
        for k in range(e.pred_lo[x], e.pred_lo[x + 1]):
            p = e.pred[k]
            if not seen[p]:
                seen[p] = True
                order[tail] = p
                tail += 1
    for s in range(count):
        if not seen[s]:
            order[tail] = s
            tail += 1
    for k in range(count - 1):  # drop the goal itself
        order[k] = order[k + 1]
    return count - 1


@njit(cache=True, error_model="numpy")
def sweep_pass(plan_eta, rng, e, g_lo, g_hi):
    """Goals ``goals[g_lo] .. goals[g_hi - 1]`` of one greedy pass on engine ``e`` over every (start, goal) pair.

    Goal-major; the starts of a goal in index order, or with ``e.ordered`` in
    :func:`sweep_order`. ``CSQL.sweep_pass`` is the calls over consecutive goal ranges
    from 0 to ``e.count`` of the unordered engine of every goal.
    """
    count = e.count
    for gi in range(g_lo, g_hi):
        g = e.goals[gi]
        if e.ordered:
            for k in range(sweep_order(e, g)):
                trial(e.order[k], g, 0.0, count, True, plan_eta, rng, e)
        else:
            for s in range(count):
                if s != g:
                    trial(s, g, 0.0, count, True, plan_eta, rng, e)
