"""The episodes of ``evaluate``: counted up front, then streamed one at a time, never all listed.

Up to six blocks the pairs come from the enumerated world (all of them in rank order, or a
seeded sample, :func:`csql_sim.core.model.pairs.selected_pairs`); past six they are drawn by
counting (:func:`csql_sim.core.model.pairs.stream_large_pairs`). Each pair gives ``seeds``
episodes; episode k of the pair of rank (or draw) i has seed ``i * seeds + k``, so every
episode's seed depends on its place in the order alone, whatever runs it.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from csql_sim.core.model.pairs import (
    check_large_pairs,
    check_sample_size,
    pair_count,
    selected_pairs,
    stream_large_pairs,
)
from csql_sim.core.state.world import MAX_BLOCKS, all_states
from csql_sim.infra.errors import CsqlError


@dataclass(frozen=True)
class EpisodeSpec:
    """One physical episode to run.

    Attributes:
        start: start configuration (notation).
        goal: goal configuration (notation).
        seed: the episode's seed.
    """

    start: str
    goal: str
    seed: int


@dataclass(frozen=True)
class Episodes:
    """The episodes of an evaluation, checked and counted; iterating yields them in order, one at a time.

    Attributes:
        n: number of blocks.
        pairs: ``"all"`` or the size K of a seeded sample of pairs.
        seeds: episodes per pair.
        sample_seed: seeds the sample.
        pair_total: the number of pairs run (all of them, or K).
    """

    n: int
    pairs: str | int
    seeds: int
    sample_seed: int
    pair_total: int

    @property
    def count(self) -> int:
        """The number of episodes."""
        return self.pair_total * self.seeds

    def __len__(self) -> int:
        return self.count

    def __iter__(self) -> Iterator[EpisodeSpec]:
        for r, start, goal in self._pairs():
            for k in range(self.seeds):
                yield EpisodeSpec(start=start, goal=goal, seed=r * self.seeds + k)

    def _pairs(self) -> Iterator[tuple[int, str, str]]:
        """(rank or draw, start notation, goal notation) of each pair in order."""
        if self.n > MAX_BLOCKS:
            drawn = stream_large_pairs(self.n, int(self.pairs), self.sample_seed)
            for r, (s, g) in enumerate(drawn):
                yield r, s.notation(), g.notation()
            return
        states = all_states(self.n)
        for r, s, g in selected_pairs(len(states), self.pairs, self.sample_seed):
            yield r, states[s].notation(), states[g].notation()

    def goal_indices(self) -> tuple[int, ...]:
        """Up to six blocks: the sorted state indices of the goals (the columns a sharded rule base reads)."""
        if self.n > MAX_BLOCKS:
            return ()
        states = len(all_states(self.n))
        if self.pairs == "all":
            return tuple(range(states))
        return tuple(sorted({g for _, _, g in selected_pairs(states, self.pairs, self.sample_seed)}))


def plan_episodes(n: int, pairs: str | int = "all", seeds: int = 1, sample_seed: int = 0) -> Episodes:
    """Check ``pairs`` and ``seeds`` for n blocks and count the episodes, listing none.

    Raises:
        CsqlError: a bad ``seeds``, a sample larger than the pairs, ``all`` past six blocks.
    """
    if isinstance(seeds, bool) or not isinstance(seeds, int) or seeds < 1:
        raise CsqlError(f"--seeds must be a positive integer, got {seeds}")
    if n > MAX_BLOCKS:
        return Episodes(n, pairs, seeds, sample_seed, check_large_pairs(pairs, n))
    total = pair_count(len(all_states(n)))
    if pairs != "all":
        check_sample_size(pairs, total)
    return Episodes(n, pairs, seeds, sample_seed, total if pairs == "all" else int(pairs))


def make_specs(n: int, pairs: str | int = "all", seeds: int = 1, sample_seed: int = 0) -> list[EpisodeSpec]:
    """Every episode of :func:`plan_episodes` as a list (for small jobs and tests; ``evaluate`` streams them).

    Args:
        n: number of blocks.
        pairs: ``"all"`` or the size of a seeded random sample of pairs.
        seeds: episodes per pair; episode k of the pair of rank i has seed ``i * seeds + k``.
        sample_seed: seeds the sample of pairs.
    """
    return list(plan_episodes(n, pairs, seeds, sample_seed))


def batches(items: Iterable[EpisodeSpec], size: int) -> Iterator[list[EpisodeSpec]]:
    """``items`` in lists of ``size`` (the last may be shorter), drawn as they are needed."""
    it = iter(items)
    while batch := list(itertools.islice(it, size)):
        yield batch
