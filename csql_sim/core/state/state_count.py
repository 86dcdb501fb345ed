"""Counting the states of n blocks, ranking them, and sampling them uniformly (exact integers).

A hand-empty configuration of m blocks is a set of towers, each an ordered list of blocks:
a "set of lists" of the m blocks, counted by

    F(0) = 1,   F(m) = sum_{k=1..m} C(m-1, k-1) * k! * F(m-k)

(the tower that holds the lowest-numbered block has k blocks: choose its other k-1
members, their order bottom-up, and the towers of the rest). F = 1, 1, 3, 13, 73, 501,
4051, ... (OEIS A000262). With at most one block held, the n-block world has

    S(n) = F(n) + n * F(n-1)

states (22 for n = 3, 7,057 for n = 6); S(n) * (S(n) - 1) ordered pairs, more than 2^63 at
n = 12. All counts are Python integers, exact at every n.

:func:`unrank_state` maps ``0 .. S(n)-1`` one-to-one onto the states (hand-empty states
first, then block A held, B held, ...; within each, the tower of the lowest block first:
its size, its members as a combination, their order as a permutation, then the rest), and
:func:`rank_state` is its inverse. :func:`sample_state` and :func:`sample_pairs` draw ranks
uniformly with one numpy Generator (:func:`uniform_below`: rejection sampling on random
bytes, exact for any size), so nothing is ever enumerated.

This numbering is not the enumerated world's goal-code order (``csql_sim.core.state.world``),
which is kept for n <= 6.
"""

from __future__ import annotations

import math

import numpy as np

from csql_sim.core.state.world import HAND, MIN_BLOCKS, TABLE, State, WorldError

MAX_COUNTED = 2000
"""The most blocks counted, ranked and sampled here (the integers have thousands of digits)."""


def check_counted_n(n: int) -> int:
    """Return ``n`` if it is 2..MAX_COUNTED, else raise WorldError."""
    if not isinstance(n, int) or isinstance(n, bool) or not MIN_BLOCKS <= n <= MAX_COUNTED:
        raise WorldError(f"number of blocks must be {MIN_BLOCKS}..{MAX_COUNTED}, got {n!r}")
    return n


_FORESTS = [1, 1]


def forest_count(m: int) -> int:
    """F(m): the hand-empty configurations of m blocks (sets of towers).

    By the sum in the module docstring, or as fast by its equivalent recurrence
    F(m) = (2m - 1) F(m-1) - (m-1)(m-2) F(m-2) (OEIS A000262), kept in a list.
    """
    while len(_FORESTS) <= m:
        k = len(_FORESTS)
        _FORESTS.append((2 * k - 1) * _FORESTS[k - 1] - (k - 1) * (k - 2) * _FORESTS[k - 2])
    return _FORESTS[m]


def _tower_term(m: int, k: int) -> int:
    """Configurations of m blocks whose lowest block's tower has k blocks."""
    return math.comb(m - 1, k - 1) * math.factorial(k) * forest_count(m - k)


def state_count(n: int) -> int:
    """S(n): the states of n blocks (hand empty, or one block held)."""
    check_counted_n(n)
    return forest_count(n) + n * forest_count(n - 1)


def count_text(count: int) -> str:
    """A count for a message: with thousands separators up to 10^15, past that its order of magnitude."""
    if count < 10**15:
        return f"{count:,}"
    return f"about 10^{int(math.log10(count))}"


def pair_count(n: int) -> int:
    """Ordered pairs of distinct states of n blocks."""
    count = state_count(n)
    return count * (count - 1)


# ---------------------------------------------------------------- combinations and permutations


def _unrank_combination(rank: int, items: list[int], k: int) -> list[int]:
    """The ``rank``-th k-subset of ``items`` in lexicographic order."""
    out, start = [], 0
    for left in range(k, 0, -1):
        for i in range(start, len(items)):
            block = math.comb(len(items) - i - 1, left - 1)
            if rank < block:
                out.append(items[i])
                start = i + 1
                break
            rank -= block
    return out


def _rank_combination(chosen: list[int], items: list[int]) -> int:
    rank, start, left = 0, 0, len(chosen)
    for c in chosen:
        i = items.index(c)
        rank += sum(math.comb(len(items) - j - 1, left - 1) for j in range(start, i))
        start, left = i + 1, left - 1
    return rank


def _unrank_permutation(rank: int, items: list[int]) -> list[int]:
    pool, out = list(items), []
    for left in range(len(items), 0, -1):
        index, rank = divmod(rank, math.factorial(left - 1))
        out.append(pool.pop(index))
    return out


def _rank_permutation(order: list[int]) -> int:
    pool, rank = sorted(order), 0
    for left, x in zip(range(len(order), 0, -1), order, strict=True):
        i = pool.index(x)
        rank += i * math.factorial(left - 1)
        pool.pop(i)
    return rank


# ---------------------------------------------------------------- forests


def _unrank_forest(rank: int, items: list[int]) -> list[list[int]]:
    """The towers (bottom-up) of configuration ``rank`` of the blocks ``items`` (sorted)."""
    towers: list[list[int]] = []
    while items:
        m, k = len(items), 1
        while rank >= (term := _tower_term(m, k)):
            rank -= term
            k += 1
        rank, rest = divmod(rank, forest_count(m - k))
        comb, perm = divmod(rank, math.factorial(k))
        members = [items[0], *_unrank_combination(comb, items[1:], k - 1)]
        towers.append(_unrank_permutation(perm, members))
        items = [b for b in items if b not in members]
        rank = rest
    return towers


def _rank_forest(towers: list[list[int]], items: list[int]) -> int:
    """Inverse of :func:`_unrank_forest`: one term per tower, from the lowest item's tower on (no recursion)."""
    rank = 0
    while items:
        m = len(items)
        tower = next(t for t in towers if items[0] in t)
        k = len(tower)
        members = sorted(tower)
        comb = _rank_combination(members[1:], items[1:])
        rank += sum(_tower_term(m, j) for j in range(1, k))
        rank += (comb * math.factorial(k) + _rank_permutation(tower)) * forest_count(m - k)
        towers = [t for t in towers if t is not tower]
        items = [b for b in items if b not in tower]
    return rank


def unrank_state(rank: int, n: int) -> State:
    """State number ``rank`` of n blocks (see the module docstring for the order)."""
    count = state_count(n)
    if not isinstance(rank, int) or not 0 <= rank < count:
        raise WorldError(f"state rank {rank!r} out of range 0..{count - 1} for {n} blocks")
    held = None
    if rank >= forest_count(n):
        held, rank = divmod(rank - forest_count(n), forest_count(n - 1))
    support = [HAND if b == held else TABLE for b in range(n)]
    for tower in _unrank_forest(rank, [b for b in range(n) if b != held]):
        for below, top in zip(tower, tower[1:], strict=False):
            support[top] = below
    return State(tuple(support))


def rank_state(state: State) -> int:
    """Inverse of :func:`unrank_state`."""
    n, held = state.n, state.held
    towers = [list(t) for t in state.towers()]
    if held is None:
        return _rank_forest(towers, list(range(n)))
    rest = _rank_forest(towers, [b for b in range(n) if b != held])
    return forest_count(n) + held * forest_count(n - 1) + rest


# ---------------------------------------------------------------- sampling


def uniform_below(bound: int, rng: np.random.Generator) -> int:
    """A uniform integer in ``0 .. bound-1`` for any positive Python integer (rejection on random bytes)."""
    if bound < 1:
        raise ValueError(f"bound must be positive, got {bound}")
    bits = (bound - 1).bit_length()
    if bits == 0:
        return 0
    size = (bits + 7) // 8
    excess = size * 8 - bits
    while True:
        value = int.from_bytes(rng.bytes(size), "big") >> excess
        if value < bound:
            return value


def sample_state(n: int, rng: np.random.Generator) -> State:
    """One state of n blocks, uniformly at random."""
    return unrank_state(uniform_below(state_count(n), rng), n)


def sample_hand_empty(n: int, rng: np.random.Generator) -> State:
    """One hand-empty state of n blocks, uniformly at random (all F(n) equally likely)."""
    check_counted_n(n)
    return unrank_state(uniform_below(forest_count(n), rng), n)


def sample_pairs(n: int, k: int, rng: np.random.Generator) -> list[tuple[State, State]]:
    """``k`` (start, goal) pairs of distinct states, each uniform over the ordered pairs (independent draws)."""
    count = state_count(n)
    out = []
    for _ in range(k):
        start, g = divmod(uniform_below(count * (count - 1), rng), count - 1)
        out.append((unrank_state(start, n), unrank_state(g + (g >= start), n)))
    return out
