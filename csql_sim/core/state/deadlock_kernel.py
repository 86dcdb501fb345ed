"""Compiled cycle counting on the deadlock graph (numba), for the move relations of large states.

The deadlock graph (:func:`csql_sim.core.state.goal_relations.precedences`) is read straight
from three arrays: ``above[b]`` (the block on b, or -1), ``goal[b]`` (b's goal support: a
block, or -1 for the table) and ``placed[b]`` (well placed). Its nodes are the misplaced
blocks; a misplaced block b has at most three out-edges: ``above[b]``, ``above[goal[b]]``
and ``goal[b]`` when that is misplaced.

:func:`deadlock_counts` finds the blocks on cycles (Tarjan, iterative) and, for every
clear block x that may move to the table, the number of blocks on cycles after that move.
A move of x to the table only removes edges into x, removes x (well placed on the table)
or adds x as a sink (x was well placed), so it changes nothing unless x is on a cycle:
only then is the graph searched again, with x on the table.
"""

from __future__ import annotations

import sys

import numpy as np

from csql_sim.infra.compiled import cached_njit

_BLAS_PROBE = "scipy.linalg.cython_blas"


def _skip_blas_probe() -> None:
    """Import numba's array functions without its BLAS probe, which imports all of SciPy's linalg (about 0.2 CPU s).

    Numba loads these kernels, cached or not, only after importing ``numba.np.arraymath``,
    which asks whether ``scipy.linalg.cython_blas`` imports; the kernels call no BLAS. With the
    probe's module marked absent for that one import the answer is no, and only jitted
    ``np.correlate``/``np.convolve`` of floats in this process use numba's own loop instead of
    BLAS (csql-sim compiles neither). Nothing is done where SciPy's linalg or numba's array
    functions are already imported; if the import fails so, numba imports them as it would.
    """
    if "scipy.linalg" in sys.modules or "numba.np.arraymath" in sys.modules or _BLAS_PROBE in sys.modules:
        return
    sys.modules[_BLAS_PROBE] = None  # type: ignore[assignment] - an import of it then fails at once
    try:
        import numba.np.arraymath  # noqa: F401
    except ImportError:
        sys.modules.pop("numba.np.arraymath", None)
    finally:
        del sys.modules[_BLAS_PROBE]


_skip_blas_probe()


@cached_njit()
def _edge(v: int, k: int, above: np.ndarray, goal: np.ndarray, placed: np.ndarray) -> int:
    """The k-th out-edge (0..2) of misplaced block v, or -1 when there is none."""
    if k == 0:
        w = above[v]
    else:
        d = goal[v]
        if d < 0:
            return -1
        w = above[d] if k == 1 else d
    if w < 0 or placed[w]:
        return -1
    return w


@cached_njit()
def _scc(nodes: np.ndarray, above: np.ndarray, goal: np.ndarray, placed: np.ndarray, comp: np.ndarray, cid: int,
         mask: np.ndarray, index: np.ndarray, low: np.ndarray, work: np.ndarray) -> int:
    """Tarjan (iterative) over ``nodes``, following only edges to blocks w with ``comp[w] == cid``.

    Sets ``mask`` of the nodes on a cycle and returns their number. With ``cid == -1`` every
    misplaced block is followed and ``comp`` receives the component numbers. ``index`` must
    be -1 on ``nodes``; ``low`` and ``work`` (4 x n) are scratch.
    """
    stack, on_stack, call, edge = work[0], work[1], work[2], work[3]
    counter, total, sp, comps = 0, 0, 0, 0
    for root in nodes:
        if placed[root] or index[root] >= 0:
            continue
        index[root] = low[root] = counter
        counter += 1
        stack[sp], on_stack[root], sp = root, 1, sp + 1
        call[0], edge[0], cp = root, 0, 1
        while cp > 0:
            v = call[cp - 1]
            k = edge[cp - 1]
            if k < 3:
                edge[cp - 1] = k + 1
                w = _edge(v, k, above, goal, placed)
                if w < 0 or (cid >= 0 and comp[w] != cid):
                    continue
                if index[w] < 0:
                    index[w] = low[w] = counter
                    counter += 1
                    stack[sp], on_stack[w], sp = w, 1, sp + 1
                    call[cp], edge[cp], cp = w, 0, cp + 1
                elif on_stack[w]:
                    low[v] = min(low[v], index[w])
                    if w == v and not mask[v]:
                        mask[v] = True
                        total += 1
                continue
            cp -= 1
            if cp > 0:
                u = call[cp - 1]
                low[u] = min(low[u], low[v])
            if low[v] == index[v]:
                top = sp
                while True:
                    sp -= 1
                    w = stack[sp]
                    on_stack[w] = 0
                    if cid < 0:
                        comp[w] = comps
                    if w == v:
                        break
                comps += 1
                if top - sp > 1:
                    for j in range(sp, top):
                        if not mask[stack[j]]:
                            mask[stack[j]] = True
                            total += 1
    return total


@cached_njit()
def deadlocked(above: np.ndarray, goal: np.ndarray, placed: np.ndarray, stuck: np.ndarray) -> int:
    """Mark the deadlocked blocks (misplaced, on a cycle) in ``stuck``; return how many."""
    n = above.shape[0]
    stuck[:] = False
    return _scc(np.arange(n), above, goal, placed, np.full(n, -1, np.int64), -1, stuck, np.full(n, -1, np.int64),
                np.zeros(n, np.int64), np.zeros((4, n), np.int64))


@cached_njit()
def deadlock_counts(support: np.ndarray, above: np.ndarray, goal: np.ndarray, placed: np.ndarray,
                    movers: np.ndarray, stuck: np.ndarray) -> np.ndarray:
    """Mark the deadlocked blocks in ``stuck``; return, per mover, the count after it moves to the table.

    Only the strongly connected component of a deadlocked mover is searched again.
    ``above`` and ``placed`` are changed for a moment and restored. A move of x to the
    table only removes edges into x, removes x (well placed on the table) or adds x as a
    sink (x was well placed): nothing changes unless x is on a cycle.
    """
    n = above.shape[0]
    index = np.full(n, -1, np.int64)
    low = np.zeros(n, np.int64)
    work = np.zeros((4, n), np.int64)
    comp = np.full(n, -1, np.int64)
    stuck[:] = False
    base = _scc(np.arange(n), above, goal, placed, comp, -1, stuck, index, low, work)
    counts = np.full(movers.shape[0], base, np.int64)
    scratch = np.zeros(n, np.bool_)
    for i in range(movers.shape[0]):
        x = movers[i]
        if not stuck[x]:
            continue
        members = np.flatnonzero(comp == comp[x])
        index[members] = -1
        scratch[members] = False
        s = support[x]
        was = placed[x]
        if s >= 0:
            above[s] = -1
        placed[x] = goal[x] < 0
        again = _scc(members, above, goal, placed, comp, comp[x], scratch, index, low, work)
        counts[i] = base - members.shape[0] + again
        if s >= 0:
            above[s] = x
        placed[x] = was
    return counts


@cached_njit()
def _source(i: int, n: int, kinds: np.ndarray, ends: np.ndarray, visitors: np.ndarray) -> int:
    """The event constraint i leaves: its source block's table visit when that is its first move, else its final."""
    a = ends[i, 0]
    return a + n if (kinds[i] & 1) and visitors[a] else a


@cached_njit()
def _back_edges(f: int, n: int, into: np.ndarray, order: np.ndarray, kinds: np.ndarray, visitors: np.ndarray,
                out: np.ndarray) -> int:
    """The indexes of the constraints that end in event f (written to ``out``); return how many.

    A visitor's final move is also entered from its own table visit (:func:`_returns` adds it).
    """
    u = f % n
    table = f >= n
    k = 0
    for j in range(into[u], into[u + 1]):
        i = order[j]
        if visitors[u] and ((kinds[i] & 2) != 0) != table:
            continue  # this constraint enters the visitor's other event
        out[k] = i
        k += 1
    return k


@cached_njit()
def _returns(b: int, n: int, first: np.ndarray, kinds: np.ndarray, ends: np.ndarray, visitors: np.ndarray,
                  into: np.ndarray, order: np.ndarray, seen: np.ndarray, back: np.ndarray, stamp: int,
                  queue: np.ndarray, bqueue: np.ndarray, scratch: np.ndarray) -> bool:
    """Whether the events' graph has a path from b's one event (b not a visitor) back to it.

    Event v is v's final move (its only move when v is no visitor), event v + n a visitor's
    table visit. Constraint i runs from ``ends[i, 0]`` to ``ends[i, 1]``: ``first[a]`` to
    ``first[a + 1]`` are the constraints leaving block a, ``order[into[a]:into[a + 1]]`` those
    entering it; ``kinds[i]`` says which ends are first moves (1: the source, 2: the target).
    Searched from both ends, forward from b and backward into it, the smaller frontier first:
    there is such a path exactly when the searches meet, and none when either runs out first.
    An event is seen (``seen`` forward, ``back`` backward) when it holds ``stamp`` there (a new
    stamp per search: nothing to clear).
    """
    queue[0], head, tail = b, 0, 1
    bqueue[0], bhead, btail = b, 0, 1
    seen[b] = stamp
    back[b] = stamp
    while head < tail and bhead < btail:
        if tail - head <= btail - bhead:
            e = queue[head]
            head += 1
            v = e % n
            table = e >= n
            if table:
                if back[v] == stamp:
                    return True
                if seen[v] != stamp:
                    seen[v] = stamp
                    queue[tail] = v
                    tail += 1
            for i in range(first[v], first[v + 1]):
                if visitors[v] and ((kinds[i] & 1) != 0) != table:
                    continue
                w = ends[i, 1]
                f = w + n if (kinds[i] & 2) and visitors[w] else w
                if f == b or back[f] == stamp:
                    return True
                if seen[f] != stamp:
                    seen[f] = stamp
                    queue[tail] = f
                    tail += 1
        else:
            f = bqueue[bhead]
            bhead += 1
            k = _back_edges(f, n, into, order, kinds, visitors, scratch)
            if f < n and visitors[f]:
                scratch[k] = -1  # the visitor's table visit precedes its final move
                k += 1
            for j in range(k):
                i = scratch[j]
                e = f + n if i < 0 else _source(i, n, kinds, ends, visitors)
                if e == b or seen[e] == stamp:
                    return True
                if back[e] != stamp:
                    back[e] = stamp
                    bqueue[btail] = e
                    btail += 1
    return False


@cached_njit()
def deadlock_cover(support: np.ndarray, above: np.ndarray, goal: np.ndarray, placed: np.ndarray,
                   stuck: np.ndarray, cover: np.ndarray) -> int:
    """Mark the cover of :mod:`csql_sim.core.state.deadlock_cover` in ``cover``; return its size.

    ``stuck`` marks the deadlocked blocks; only constraints between them can lie on a cycle.
    Every deadlocked block starts as a visitor (enough: no cycle is left) and is dropped, lowest
    in its tower first (ties: block order), unless that closes a cycle, which then runs through
    the dropped block's one event (:func:`_returns`).
    """
    n = above.shape[0]
    kinds = np.zeros(3 * n, np.int64)
    ends = np.zeros((3 * n, 2), np.int64)
    k = 0
    for b in range(n):
        if not stuck[b]:
            continue
        x = above[b]
        if x >= 0 and stuck[x]:  # the block on b leaves first: first(x) -> first(b)
            kinds[k], ends[k, 0], ends[k, 1], k = 3, x, b, k + 1
        d = goal[b]
        if d >= 0:
            top = above[d]
            if top >= 0 and stuck[top]:  # the block on b's goal support leaves first: first(top) -> final(b)
                kinds[k], ends[k, 0], ends[k, 1], k = 1, top, b, k + 1
            if stuck[d] and not placed[d]:  # b's goal support arrives first: final(d) -> final(b)
                kinds[k], ends[k, 0], ends[k, 1], k = 0, d, b, k + 1
    order = np.argsort(ends[:k, 0], kind="mergesort")
    kinds, ends = kinds[:k][order], ends[:k][order]
    first = np.zeros(n + 1, np.int64)
    for i in range(k):
        first[ends[i, 0] + 1] += 1
    for a in range(n):
        first[a + 1] += first[a]
    heights = np.zeros(n, np.int64)
    for b in range(n):
        c = b
        while support[c] >= 0:
            c = support[c]
            heights[b] += 1
    order_in = np.argsort(ends[:, 1], kind="mergesort")
    into = np.zeros(n + 1, np.int64)
    for i in range(k):
        into[ends[i, 1] + 1] += 1
    for a in range(n):
        into[a + 1] += into[a]
    cover[:] = stuck
    seen = np.zeros(2 * n, np.int64)
    back = np.zeros(2 * n, np.int64)
    queue = np.zeros(2 * n, np.int64)
    bqueue = np.zeros(2 * n, np.int64)
    scratch = np.zeros(4, np.int64)
    size = int(stuck.sum())
    stamp = 0
    for b in np.argsort(heights * n + np.arange(n)):
        if not cover[b]:
            continue
        cover[b] = False
        stamp += 1
        if _returns(b, n, first, kinds, ends, cover, into, order_in, seen, back, stamp, queue, bqueue, scratch):
            cover[b] = True
        else:
            size -= 1
    return size
