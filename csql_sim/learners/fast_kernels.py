"""Compiled inner loops of the array-backed CS-QL engine (:mod:`csql_sim.learners.fast_engine`).

Every function mirrors one piece of the reference engine (:mod:`csql_sim.learners.cs_ql`,
:mod:`csql_sim.learners.trial`, :mod:`csql_sim.learners.selection`) operation for
operation, so that the same uniforms give the same floating-point results:

* :func:`trial` is :func:`~csql_sim.learners.trial.run_trial` with CS-QL's ``act``
  (eq. 3 exactly as :func:`~csql_sim.learners.selection.boltzmann` computes it: the first
  largest value, ``exp((v - top) / T)``, the weights summed as Python's ``sum`` does, the
  cumulative draw), ``learn`` (eq. 1, 2) and, with ``plan_eta > 0``, ``update_all``;
* :func:`run_trials` is :func:`~csql_sim.learners.trial.run_training`;
* :func:`sweep_pass` is one pass of :meth:`~csql_sim.learners.cs_ql.CSQL.sweep`.

The trial loop is written out in one function on purpose: numba's IR-level inlining of
small helpers cost reference-count traffic on every step (about 10x slower).

Memory layout. A *node* is a (state, goal) pair that has been posted; nodes are numbered
in the order they were first processed, and node ``j``'s Q-classifiers are the
consecutive slots ``off[j] .. off[j] + legal count`` of ``q``, ``err`` and ``last`` (the
candidates in precondition-rule order). That is the reference's classifier-list order.

Counters live in one int64 array ``ctr`` (indices below), so a run can pause for a
progress bar and resume. The uniform stream is the reference's: ``rng.random(BATCH)``
batches (numba draws from the same ``numpy.random.Generator``, the same numbers), one
uniform per selection, two per random task.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

NODES, CLS, T, POS, K, PHASE = range(6)
"""Indices into ``ctr``: nodes used, classifier slots used, clock, stream position,
trial index, phase within a trial index (0 test task, 1 random task)."""
CTR_SIZE = 6
DONE, PAUSED = 0, 1


@njit(cache=True, error_model="numpy")
def new_node(s, g, t, count, node_id, node_off, node_state, node_born, q, err, last, lo_legal, ctr, q0):
    """Process (cover) the node of (s, g) at clock ``t``: its Q-classifiers get the next slots."""
    j = ctr[NODES]
    ctr[NODES] = j + 1
    node_id[s * count + g] = j
    off = ctr[CLS]
    nl = lo_legal[s + 1] - lo_legal[s]
    ctr[CLS] = off + nl
    node_off[j] = off
    node_state[j] = s
    node_born[j] = t
    for i in range(nl):
        q[off + i] = q0
        err[off + i] = 0.0
        last[off + i] = t
    return j


@njit(cache=True, error_model="numpy")
def trial(start, goal, temperature, cap, track, plan_eta, rng, buf, ctr, count, lo_legal, nxt_state, node_id,
          node_off, node_state, node_born, q, err, last, q0, gamma, eta, payoff, compensated, scratch):
    """One trial; returns (steps, reached, value_sum). ``plan_eta > 0``: Dyna backups of every candidate."""
    t = ctr[T]
    pos = ctr[POS]
    size = buf.shape[0]
    j = node_id[start * count + goal]
    if j < 0:
        j = new_node(start, goal, t, count, node_id, node_off, node_state, node_born, q, err, last, lo_legal,
                     ctr, q0)
    value_sum = 0.0
    t0 = t
    end = t0 + cap
    reached = False
    while t < end:
        s = node_state[j]
        off = node_off[j]
        lo = lo_legal[s]
        nl = lo_legal[s + 1] - lo
        if pos >= size:  # the stream's next batch
            buf[:] = rng.random(size)
            pos = 0
        u = buf[pos]
        pos += 1
        i = 0  # eq. 3; a lone candidate is taken without it (the uniform is spent either way)
        if nl > 1:
            top = q[off]
            for k in range(1, nl):
                if q[off + k] > top:
                    top = q[off + k]
            if temperature <= 0.0:
                for k in range(nl):
                    if q[off + k] == top:
                        i = k
                        break
            else:
                for k in range(nl):
                    scratch[k] = math.exp((q[off + k] - top) / temperature)
                total = scratch[0]
                comp = 0.0
                for k in range(1, nl):
                    x = scratch[k]
                    sm = total + x
                    if compensated:  # Python >= 3.12: sum() of floats is Neumaier-compensated
                        if abs(total) >= abs(x):
                            comp += (total - sm) + x
                        else:
                            comp += (x - sm) + total
                    total = sm
                if compensated and comp != 0.0 and math.isfinite(comp):
                    total += comp
                x = u * total
                acc = 0.0
                i = nl - 1
                for k in range(nl):
                    acc += scratch[k]
                    if x < acc:
                        i = k
                        break
        c = off + i
        if track:
            value_sum += q[c]
        ns = nxt_state[lo + i]
        nj = -1
        target = payoff
        if ns != goal:
            nj = node_id[ns * count + goal]
            if nj < 0:
                nj = new_node(ns, goal, t, count, node_id, node_off, node_state, node_born, q, err, last, lo_legal,
                              ctr, q0)
            noff = node_off[nj]
            best = -np.inf
            for d in range(noff, noff + lo_legal[ns + 1] - lo_legal[ns]):
                if q[d] > best:
                    best = q[d]
            target = gamma * best
        t += 1
        if plan_eta > 0.0:  # CSQL.update_all: successors in candidate order at t - 1, then every backup
            for k in range(nl):
                ks = nxt_state[lo + k]
                if ks != goal and node_id[ks * count + goal] < 0:
                    new_node(ks, goal, t - 1, count, node_id, node_off, node_state, node_born, q, err, last,
                             lo_legal, ctr, q0)
            for k in range(nl):
                ks = nxt_state[lo + k]
                kt = payoff
                if ks != goal:
                    koff = node_off[node_id[ks * count + goal]]
                    best = -np.inf
                    for d in range(koff, koff + lo_legal[ks + 1] - lo_legal[ks]):
                        if q[d] > best:
                            best = q[d]
                    kt = gamma * best
                eps = kt - q[off + k]
                q[off + k] += plan_eta * eps
                err[off + k] = eps if eps >= 0.0 else -eps
                last[off + k] = t
        else:  # eq. 1 and 2
            eps = target - q[c]
            q[c] += eta * eps
            err[c] = eps if eps >= 0.0 else -eps
            last[c] = t
        if nj < 0:
            reached = True
            break
        j = nj
    ctr[T] = t
    ctr[POS] = pos
    return t - t0, reached, value_sum


@njit(cache=True, error_model="numpy")
def run_trials(trials, k_stop, test_every, test_start, test_goal, t0, t_decay, t_min, cap, rng, buf, ctr, count,
               lo_legal, nxt_state, node_id, node_off, node_state, node_born, q, err, last, q0, gamma, eta, payoff,
               compensated, scratch, curve_steps, curve_values):
    """``run_training``: the test task every ``test_every`` trials and the random tasks.

    Stops with PAUSED when trial ``k_stop`` is due (for a progress bar), DONE after the
    test task that follows the last trial.
    """
    size = buf.shape[0]
    while True:
        k = ctr[K]
        temperature = t0 * t_decay ** np.float64(k)  # CommonParams.temperature, operation for operation
        if not temperature > t_min:
            temperature = t_min
        if ctr[PHASE] == 0:
            if k == k_stop and k < trials:
                return PAUSED
            if test_every > 0 and k % test_every == 0:
                steps, _, vsum = trial(test_start, test_goal, temperature, cap, True, 0.0, rng, buf, ctr, count,
                                       lo_legal, nxt_state, node_id, node_off, node_state, node_born, q, err, last,
                                       q0, gamma, eta, payoff, compensated, scratch)
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
        start = min(int(u * count), count - 1)
        goal = min(int(v * (count - 1)), count - 2)
        if goal >= start:
            goal += 1
        trial(start, goal, temperature, cap, False, 0.0, rng, buf, ctr, count, lo_legal, nxt_state, node_id,
              node_off, node_state, node_born, q, err, last, q0, gamma, eta, payoff, compensated, scratch)
        ctr[K] = k + 1
        ctr[PHASE] = 0


@njit(cache=True, error_model="numpy")
def sweep_pass(plan_eta, rng, buf, ctr, count, lo_legal, nxt_state, node_id, node_off, node_state, node_born, q, err,
               last, q0, gamma, eta, payoff, compensated, scratch):
    """One greedy pass over every (start, goal) pair, goal-major (``CSQL.sweep_pass``)."""
    for g in range(count):
        for s in range(count):
            if s != g:
                trial(s, g, 0.0, count, True, plan_eta, rng, buf, ctr, count, lo_legal, nxt_state, node_id,
                      node_off, node_state, node_born, q, err, last, q0, gamma, eta, payoff, compensated, scratch)
