"""Ordered pairs of distinct states, ranked, sampled and streamed without listing them.

Rank ``r`` in ``0 .. S(S-1) - 1`` names the pair ``(start, goal)`` in start-major order:
``start = r // (S - 1)``, and the goal is the ``(r % (S - 1))``-th state other than
``start``. For n = 6 there are 7057 states and 49,794,192 pairs; sampling K of them
costs O(K) time and memory, and :func:`all_pairs` yields them one at a time.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

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
