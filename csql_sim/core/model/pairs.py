"""Ordered pairs of distinct states, ranked, sampled and streamed without listing them.

Rank ``r`` in ``0 .. S(S-1) - 1`` names the pair ``(start, goal)`` in start-major order:
``start = r // (S - 1)``, and the goal is the ``(r % (S - 1))``-th state other than
``start``. For n = 6 there are 7057 states and 49,794,192 pairs; sampling K of them
costs O(K) time and memory, and :func:`all_pairs` yields them one at a time.

Past six blocks (7..26) the world is never listed: :func:`check_large_pairs` refuses up
front a job that would enumerate (``all``, or K beyond the number of pairs, naming the
exact count) and :func:`stream_large_pairs` draws K pairs uniformly by counting
(:func:`csql_sim.core.state.state_count.sample_pairs`, exact integers), one at a time.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from csql_sim.core.state import state_count
from csql_sim.core.state.world import MAX_BLOCKS, State
from csql_sim.infra.errors import CsqlError


def pair_count(states: int) -> int:
    """The number of ordered pairs of distinct states."""
    return states * (states - 1)


def unrank(rank: int, states: int) -> tuple[int, int]:
    """The (start, goal) state indices of pair ``rank`` (start-major order)."""
    if not 0 <= rank < pair_count(states):
        raise CsqlError(f"pair rank {rank} out of range for {states} states")
    start, k = divmod(rank, states - 1)
    return start, k + (k >= start)


def rank(start: int, goal: int, states: int) -> int:
    """Inverse of :func:`unrank`."""
    if start == goal or not (0 <= start < states and 0 <= goal < states):
        raise CsqlError(f"({start}, {goal}) is not a pair of distinct states of {states}")
    return start * (states - 1) + goal - (goal > start)


def check_sample_size(k: int, total: int) -> None:
    """``--pairs K``: a positive integer, at most the ``total`` number of pairs (the error names it)."""
    if not isinstance(k, int) or isinstance(k, bool) or k < 1:
        raise CsqlError(f"--pairs must be 'all' or a positive integer, got {k!r}")
    if k > total:
        raise CsqlError(f"--pairs {k} is more than the {total} start/goal pairs")


def sample_ranks(states: int, k: int, seed: int = 0) -> list[int]:
    """``k`` distinct pair ranks drawn without replacement by a seeded generator, sorted.

    ``Generator.choice`` without replacement draws small samples by Floyd's method
    (O(k)); the pairs themselves are never listed. ``k`` equal to the number of pairs
    gives every rank; more is an error naming the number.
    """
    total = pair_count(states)
    check_sample_size(k, total)
    if k >= total:
        return list(range(total))
    return sorted(int(i) for i in np.random.default_rng(seed).choice(total, k, replace=False))


def all_pairs(states: int) -> Iterator[tuple[int, int]]:
    """Every (start, goal) pair in rank order, one at a time."""
    for start in range(states):
        for goal in range(states):
            if goal != start:
                yield start, goal


def parse_pairs(text: str) -> str | int:
    """``all`` or a positive integer, as given to ``--pairs``."""
    if text.strip().lower() == "all":
        return "all"
    try:
        value = int(text)
    except ValueError:
        raise CsqlError(f"--pairs must be 'all' or a positive integer, got {text!r}") from None
    if value < 1:
        raise CsqlError(f"--pairs must be 'all' or a positive integer, got {text!r}")
    return value


def selected_pairs(states: int, pairs: str | int, seed: int = 0) -> Iterator[tuple[int, int, int]]:
    """(rank, start, goal) of every pair, or of a seeded sample of ``pairs`` of them."""
    if pairs == "all":
        for r, (start, goal) in enumerate(all_pairs(states)):
            yield r, start, goal
        return
    for r in sample_ranks(states, pairs, seed):
        yield (r, *unrank(r, states))


def rounded(count: int) -> str:
    """A large exact count in words a person reads at a glance: ``4.8 x 10^11`` (below 10^6 as is)."""
    if count < 10**6:
        return f"{count:,}"
    digits = len(str(count)) - 1
    mantissa = f"{count / 10**digits:.1f}"  # int / int: correctly rounded at any size
    if mantissa == "10.0":
        mantissa, digits = "1.0", digits + 1
    return f"{mantissa} x 10^{digits}"


def check_large_pairs(pairs: str | int, n: int) -> int:
    """Refuse a ``--pairs`` job at n > 6 blocks that would enumerate; return the sample size K.

    ``all`` would list every ordered pair (4.8 x 10^11 at n = 8), and a K larger than the
    number of pairs cannot be drawn without repeats; both are refused before any work
    with one line naming the exact count.

    Raises:
        CsqlError: one line naming the number of pairs.
    """
    if n <= MAX_BLOCKS:
        raise CsqlError(f"{n} blocks: samples up to {MAX_BLOCKS} blocks are drawn from the enumerated world")
    total = state_count.pair_count(n)
    where = f"{n} blocks have {total:,} ordered start/goal pairs ({rounded(total)})"
    if pairs == "all":
        raise CsqlError(f"--pairs all would enumerate every pair: {where}; past {MAX_BLOCKS} blocks give "
                        f"--pairs K, a uniform random sample")
    if not isinstance(pairs, int) or isinstance(pairs, bool) or pairs < 1:
        raise CsqlError(f"--pairs must be 'all' or a positive integer, got {pairs!r}")
    if pairs > total:
        raise CsqlError(f"--pairs {pairs:,} is more than the pairs there are: {where}")
    return pairs


def stream_large_pairs(n: int, k: int, seed: int) -> Iterator[tuple[State, State]]:
    """K (start, goal) pairs of n blocks, each uniform over the ordered pairs, drawn one at a time.

    The generator is ``numpy.random.default_rng(seed)``; the pairs are exactly those of
    ``state_count.sample_pairs(n, k, default_rng(seed))`` (independent draws, in order),
    without holding them all.
    """
    rng = np.random.default_rng(seed)
    for _ in range(k):
        yield state_count.sample_pairs(n, 1, rng)[0]
