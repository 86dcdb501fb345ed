"""Agreement with the hand ordering: how often a lifted file's policy picks the hand ordering's move.

A **move** is a pick and the put that follows (:class:`~csql_sim.core.state.moves.Move`):
a policy's move in a hand-empty state is the block it picks and where it then puts it (``act``
twice); holding a block, it is where it puts it. It is asked through the policy contract, so
given-atom files, generated-feature files, committees and the named baselines are all measured
the same way.

A file's **agreement** is the share of sampled states in which its move equals the move of
the hand ordering (:func:`~csql_sim.core.policies.hand_ordering.hand_ordering`, the six ranks
over the given atoms, ``cover`` included). A file at 100% is described as "a learned ranking
of the given atoms": on the sample it chooses as that fixed ranking does.

**The sample** (:func:`agreement_states`): one :class:`numpy.random.Generator` seeded with
:data:`AGREEMENT_SEED` draws :data:`AGREEMENT_STATES` start/goal pairs at each n of
:data:`AGREEMENT_SIZES` in turn (10, then 20, then 40), each pair uniform over the ordered
pairs of distinct states (a block may be held)
(:func:`~csql_sim.core.state.state_count.sample_pairs`, the draw of the benchmark's pairs).
Pairs at the goal are never drawn, so every sampled state has a move. 100 states per n keep
``csql-sim show --rules FILE`` to a few seconds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csql_sim.core.policies.contract import Policy
from csql_sim.core.policies.hand_ordering import hand_ordering
from csql_sim.core.state.moves import Move
from csql_sim.core.state.state import State
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.core.state.world import TABLE, ActionKind, successor

AGREEMENT_SEED = 48
"""The seed of the agreement sample's generator."""
AGREEMENT_SIZES = (10, 20, 40)
"""The numbers of blocks sampled, drawn in this order."""
AGREEMENT_STATES = 100
"""Start/goal pairs drawn per number of blocks."""


def agreement_states(sizes: tuple[int, ...] = AGREEMENT_SIZES, count: int = AGREEMENT_STATES,
                     seed: int = AGREEMENT_SEED) -> dict[int, list[tuple[State, State]]]:
    """The sample of the module docstring: ``count`` uniform pairs per n, one generator, sizes in turn."""
    rng = np.random.default_rng(seed)
    return {n: sample_pairs(n, count, rng) for n in sizes}


def move_of(policy: Policy, state: State, goal: State) -> Move | None:
    """The move ``policy`` makes from ``state``: its pick and the put after it, or the held block's put.

    None when it stops (at the goal, or no move), or when its last action is a goal's final pick.
    """
    pick = None
    if state.held is None:
        pick = policy.act(state, goal)
        if pick is None or not pick.is_pick:
            return None
    put = policy.act(state if pick is None else successor(state, pick), goal)
    if put is None or put.is_pick:
        return None
    return Move(put.block, TABLE if put.kind is ActionKind.PUTDOWN else put.target)


@dataclass(frozen=True)
class Agreement:
    """Per n, how many sampled states the two policies' moves agree in, of how many."""

    agreed: dict[int, int]
    states: dict[int, int]

    @property
    def share(self) -> float:
        """The share of all sampled states in agreement (0..1)."""
        return sum(self.agreed.values()) / max(1, sum(self.states.values()))

    @property
    def complete(self) -> bool:
        """Whether the moves agree in every sampled state."""
        return self.agreed == self.states

    def text(self) -> str:
        """``100.0% (n = 10: 100/100, n = 20: ...)``."""
        parts = ", ".join(f"n = {n}: {self.agreed[n]}/{self.states[n]}" for n in self.states)
        return f"{100 * self.share:.1f}% ({parts})"

    def describe(self) -> str:
        """One line for ``show``: the agreement, the sample, and at 100% "a learned ranking of the given atoms"."""
        line = (f"agreement with the hand ordering: {self.text()} of uniform states, seed {AGREEMENT_SEED}")
        return f"{line}: a learned ranking of the given atoms" if self.complete else line

    def as_dict(self) -> dict:
        """The JSON of ``show --json``."""
        return {"share": self.share, "agreed": {str(n): k for n, k in self.agreed.items()},
                "states": {str(n): k for n, k in self.states.items()}, "seed": AGREEMENT_SEED,
                "learned_ranking_of_given_atoms": self.complete}


def agreement(policy: Policy, states: dict[int, list[tuple[State, State]]] | None = None,
              reference: Policy | None = None) -> Agreement:
    """How often ``policy`` makes the move of ``reference`` (default: the hand ordering) on ``states``.

    ``states`` defaults to :func:`agreement_states`.
    """
    states = agreement_states() if states is None else states
    reference = hand_ordering() if reference is None else reference
    agreed = {n: sum(move_of(policy, s, g) == move_of(reference, s, g) for s, g in pairs)
              for n, pairs in states.items()}
    return Agreement(agreed, {n: len(pairs) for n, pairs in states.items()})
