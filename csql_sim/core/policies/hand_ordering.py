"""The hand ordering: a fixed ranking of the given atoms, written once (a comparator, not a learner).

The lifted Q-classifiers (:mod:`csql_sim.core.policies.lifted_policy`) rank the moves of a
state by the relations of :data:`~csql_sim.core.state.atom_names.ATOMS`. The **hand
ordering** ranks them by hand over the same atoms, ``cover`` included; the first move (in
move order) of the best rank is taken:

1. the goal move: ``misplaced(?x)``, ``goal-on(?x,?d)`` and ``ready(?d)``;
2. a table move of a ``cover(?x)`` block;
3. a table move of a ``deadlocked(?x)`` block;
4. a table move of a misplaced block with ``above-needed(?x)``;
5. another table move;
6. a block move.

:func:`hand_ordering` gives it as a :class:`LiftedPolicy` of fully specific classifiers (one
per relation pattern and kind, its advantage the rank), so it plans through the same code as
a learned file. :func:`hand_ordering_without_cover` is the ordering the docs used before
(the goal move, then ``least-stuck``, ``deadlocked``, ``above-needed``, any other move of a
misplaced block, a well-placed block's move): it leaves ``cover`` out, so a learned file
that reads ``cover`` must not be credited with the gap to it.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

from csql_sim.core.policies.lifted_classifier import LiftedQClassifier
from csql_sim.core.policies.lifted_policy import LiftedPolicy
from csql_sim.core.state.atom_names import ATOMS
from csql_sim.core.state.moves import KINDS

Bits = tuple[int, ...]


def hand_rank(bits: Bits, kind: str) -> int:
    """The rank (0 best .. 5) of a move with relations ``bits`` (:data:`ATOMS` order) and kind ``kind``."""
    misplaced, goal_on, ready, stuck, above = bits[:5]
    cover = bits[8]
    if misplaced and goal_on and ready:
        return 0
    if kind == "block":
        return 5
    if cover:
        return 1
    if stuck:
        return 2
    return 3 if misplaced and above else 4


def rank_without_cover(bits: Bits, kind: str) -> int:
    """The older ordering's rank, which leaves ``cover`` out (module docstring)."""
    misplaced, goal_on, ready, stuck, above, least = bits[:6]
    if not misplaced:
        return 5
    return 0 if goal_on and ready else 1 if least else 2 if stuck else 3 if above else 4


def ranking_policy(rank: Callable[[Bits, str], int], method: str) -> LiftedPolicy:
    """A ranking of the atoms as lifted classifiers: one per relation pattern and kind, advantage = rank."""
    out = [LiftedQClassifier("".join(map(str, bits)), kind, float(rank(bits, kind)))
           for bits in itertools.product((0, 1), repeat=len(ATOMS)) for kind in KINDS]
    return LiftedPolicy(out, {"method": method})


def hand_ordering() -> LiftedPolicy:
    """The six-rank hand ordering over the given atoms, ``cover`` included (module docstring)."""
    return ranking_policy(hand_rank, "hand ordering")


def hand_ordering_without_cover() -> LiftedPolicy:
    """The older hand ordering, without ``cover`` (named ``hand-without-cover`` in tables)."""
    return ranking_policy(rank_without_cover, "hand-without-cover")
