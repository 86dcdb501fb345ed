"""Compiled inner loops of the array-backed CS-QL engine (:mod:`csql_sim.learners.fast_engine`).

Every function mirrors one piece of the reference engine (:mod:`csql_sim.learners.csql`,
:mod:`csql_sim.learners.base`, :mod:`csql_sim.learners.selection`) operation for
operation, so that the same uniforms give the same floating-point results:

* :func:`select` is :func:`~csql_sim.learners.selection.boltzmann` (the first largest
  value, ``exp((v - top) / T)``, the weights summed as Python's ``sum`` does, then the
  cumulative draw);
* :func:`trial` is :meth:`~csql_sim.learners.base.Learner.run_trial` with CS-QL's
  ``select``, ``successor`` and ``update`` (eq. 1, 2);
* :func:`run_trials` is :meth:`~csql_sim.learners.base.Learner.run`;
* :func:`sweep_pass` is one pass of :meth:`~csql_sim.learners.csql.CSQL.sweep`.

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


@njit(cache=True, inline="always", error_model="numpy")
def uniform(rng, buf, ctr):
    """The next uniform of the stream: ``buf`` refilled with ``rng.random(len(buf))`` when spent."""
    pos = ctr[POS]
    if pos >= buf.shape[0]:
        buf[:] = rng.random(buf.shape[0])
        pos = 0
    ctr[POS] = pos + 1
    return buf[pos]


@njit(cache=True, inline="always", error_model="numpy")
def get_node(s, g, t, count, node_id, node_off, node_state, node_born, q, err, last, lo_legal, ctr, q0):
    """The node of (s, g), processed (covered) at clock ``t`` on first use."""
    key = s * count + g
    j = node_id[key]
    if j < 0:
        j = ctr[NODES]
        ctr[NODES] = j + 1
        node_id[key] = j
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


@njit(cache=True, inline="always", error_model="numpy")
def select(q, off, nl, temperature, u, compensated, scratch):
    """Eq. 3 exactly as ``boltzmann`` computes it; a lone candidate is taken without it."""
    if nl == 1:
        return 0
    top = q[off]
    for i in range(1, nl):
        if q[off + i] > top:
            top = q[off + i]
    if temperature <= 0.0:
        for i in range(nl):
            if q[off + i] == top:
                return i
        return 0
    w = scratch
    for i in range(nl):
        w[i] = math.exp((q[off + i] - top) / temperature)
    total = w[0]
    comp = 0.0
    for i in range(1, nl):
        x = w[i]
        s = total + x
        if compensated:  # Python >= 3.12: sum() of floats is Neumaier-compensated
            if abs(total) >= abs(x):
                comp += (total - s) + x
            else:
                comp += (x - s) + total
        total = s
    if compensated and comp != 0.0 and math.isfinite(comp):
        total += comp
    x = u * total
    acc = 0.0
    for i in range(nl):
        acc += w[i]
        if x < acc:
            return i
    return nl - 1


@njit(cache=True, inline="always", error_model="numpy")
def update(c, target, t, q, err, last, eta):
    """Eq. 1 and 2 on classifier ``c``; |epsilon| and the step recorded."""
    eps = target - q[c]
    q[c] += eta * eps
    err[c] = eps if eps >= 0.0 else -eps
    last[c] = t


@njit(cache=True, inline="always", error_model="numpy")
def backup(
    off,
    lo,
    nl,
    goal,
    t,
    count,
    lo_legal,
    nxt_state,
    node_id,
    node_off,
    node_state,
    node_born,
    q,
    err,
    last,
    ctr,
    q0,
    gamma,
    eta,
    payoff,
):
    """``CSQL.update_all``: every candidate's successor (created at ``t - 1``), then eq. 1-2 for each."""
    for k in range(nl):
        ns = nxt_state[lo + k]
        if ns != goal:
            get_node(ns, goal, t - 1, count, node_id, node_off, node_state, node_born, q, err, last, lo_legal, ctr, q0)
    for k in range(nl):
        ns = nxt_state[lo + k]
        if ns == goal:
            target = payoff
        else:
            nj = node_id[ns * count + goal]
            noff = node_off[nj]
            best = -np.inf
            for d in range(noff, noff + lo_legal[ns + 1] - lo_legal[ns]):
                if q[d] > best:
                    best = q[d]
            target = gamma * best
        update(off + k, target, t, q, err, last, eta)


@njit(cache=True, inline="always", error_model="numpy")
def trial(
    start,
    goal,
    temperature,
    cap,
    track,
    plan_eta,
    rng,
    buf,
    ctr,
    count,
    lo_legal,
    nxt_state,
    node_id,
    node_off,
    node_state,
    node_born,
    q,
    err,
    last,
    q0,
    gamma,
    eta,
    payoff,
    compensated,
    scratch,
):
    """One trial (``run_trial``); returns (steps, reached, value_sum)."""
    t = ctr[T]
    pos = ctr[POS]
    size = buf.shape[0]
    j = get_node(start, goal, t, count, node_id, node_off, node_state, node_born, q, err, last, lo_legal, ctr, q0)
    value_sum = 0.0
    t0 = t
    end = t0 + cap
    reached = False
    while t < end:
        s = node_state[j]
        off = node_off[j]
        lo = lo_legal[s]
        nl = lo_legal[s + 1] - lo
        if pos >= size:  # uniform(): the stream's next batch
            buf[:] = rng.random(size)
            pos = 0
        i = select(q, off, nl, temperature, buf[pos], compensated, scratch)
        pos += 1
        c = off + i
        if track:
            value_sum += q[c]
        ns = nxt_state[lo + i]
        if ns == goal:
            target = payoff
            nj = -1
        else:
            nj = get_node(ns, goal, t, count, node_id, node_off, node_state, node_born, q, err, last, lo_legal, ctr, q0)
            noff = node_off[nj]
            nn = lo_legal[ns + 1] - lo_legal[ns]
            best = -np.inf
            for d in range(noff, noff + nn):
                if q[d] > best:
                    best = q[d]
            target = gamma * best
        t += 1
        if plan_eta > 0.0:  # the Dyna sweep: every candidate, step plan_eta
            backup(
                off,
                lo,
                nl,
                goal,
                t,
                count,
                lo_legal,
                nxt_state,
                node_id,
                node_off,
                node_state,
                node_born,
                q,
                err,
                last,
                ctr,
                q0,
                gamma,
                plan_eta,
                payoff,
            )
        else:
            update(c, target, t, q, err, last, eta)
        if nj < 0:
            reached = True
            break
        j = nj
    ctr[T] = t
    ctr[POS] = pos
    return t - t0, reached, value_sum


@njit(cache=True, error_model="numpy")
def run_trials(
    trials,
    k_stop,
    test_every,
    test_start,
    test_goal,
    t0,
    t_decay,
    t_min,
    cap,
    rng,
    buf,
    ctr,
    count,
    lo_legal,
    nxt_state,
    node_id,
    node_off,
    node_state,
    node_born,
    q,
    err,
    last,
    q0,
    gamma,
    eta,
    payoff,
    compensated,
    scratch,
    curve_steps,
    curve_values,
):
    """``Learner.run``: the test task every ``test_every`` trials and the random tasks.

    Stops with PAUSED when trial ``k_stop`` is due (for a progress bar), DONE after the
    test task that follows the last trial.
    """
    while True:
        k = ctr[K]
        temperature = t0 * t_decay ** np.float64(k)  # CommonParams.temperature, operation for operation
        if not temperature > t_min:
            temperature = t_min
        if ctr[PHASE] == 0:
            if k == k_stop and k < trials:
                return PAUSED
            if test_every > 0 and k % test_every == 0:
                steps, _, vsum = trial(
                    test_start,
                    test_goal,
                    temperature,
                    cap,
                    True,
                    0.0,
                    rng,
                    buf,
                    ctr,
                    count,
                    lo_legal,
                    nxt_state,
                    node_id,
                    node_off,
                    node_state,
                    node_born,
                    q,
                    err,
                    last,
                    q0,
                    gamma,
                    eta,
                    payoff,
                    compensated,
                    scratch,
                )
                m = k // test_every
                curve_steps[m] = steps
                curve_values[m] = vsum / steps if steps else 0.0
            if k == trials:
                return DONE
            ctr[PHASE] = 1
        u = uniform(rng, buf, ctr)
        v = uniform(rng, buf, ctr)
        start = min(int(u * count), count - 1)
        goal = min(int(v * (count - 1)), count - 2)
        if goal >= start:
            goal += 1
        trial(
            start,
            goal,
            temperature,
            cap,
            False,
            0.0,
            rng,
            buf,
            ctr,
            count,
            lo_legal,
            nxt_state,
            node_id,
            node_off,
            node_state,
            node_born,
            q,
            err,
            last,
            q0,
            gamma,
            eta,
            payoff,
            compensated,
            scratch,
        )
        ctr[K] = k + 1
        ctr[PHASE] = 0


@njit(cache=True, error_model="numpy")
def sweep_pass(
    plan_eta,
    rng,
    buf,
    ctr,
    count,
    lo_legal,
    nxt_state,
    node_id,
    node_off,
    node_state,
    node_born,
    q,
    err,
    last,
    q0,
    gamma,
    eta,
    payoff,
    compensated,
    scratch,
):
    """One greedy pass over every (start, goal) pair, goal-major (``CSQL.sweep``'s inner loops)."""
    for g in range(count):
        for s in range(count):
            if s != g:
                trial(
                    s,
                    g,
                    0.0,
                    count,
                    True,
                    plan_eta,
                    rng,
                    buf,
                    ctr,
                    count,
                    lo_legal,
                    nxt_state,
                    node_id,
                    node_off,
                    node_state,
                    node_born,
                    q,
                    err,
                    last,
                    q0,
                    gamma,
                    eta,
                    payoff,
                    compensated,
                    scratch,
                )
