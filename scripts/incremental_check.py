"""Check that the lifted policy's incremental relations give the plans of the from-scratch ones.

    python scripts/incremental_check.py [--pairs 1000] [--seed 0] [--sizes 7-26]
                                        [--rules assets/rules/lifted.json]

Per n, K pairs drawn uniformly by counting (one generator seeded once, sizes in order) are
planned twice with the same lifted Q-classifiers: once with
:class:`~csql_sim.core.state.relation_tracker.RelationTracker` (the policy as shipped) and once
with every relation of every state computed from scratch
(:class:`~csql_sim.core.state.move_relations.MoveRelations`, the policy as it was). Prints one
line per n; exits 1 at the first pair whose plans differ.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from csql_sim.core.policies.lifted_policy import LiftedPolicy, load_lifted_policy
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.move_relations import MoveRelations
from csql_sim.core.state.state import State
from csql_sim.core.state.state_count import sample_pairs


class FromScratch(LiftedPolicy):
    """The lifted policy with every relation computed from scratch in every state."""

    def relations(self, state: State, target: State) -> MoveRelations:  # type: ignore[override]
        """From scratch, as before the incremental relations."""
        return MoveRelations(state, target)


def main(argv: list[str] | None = None) -> int:
    """Plan every pair both ways and compare."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=1000, help="pairs per n (default 1000)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the one generator (default 0)")
    parser.add_argument("--sizes", default="7-26", help="first-last number of blocks (default 7-26)")
    parser.add_argument("--rules", default="assets/rules/lifted.json", help="lifted Q-classifier file")
    args = parser.parse_args(argv)
    first, _, last = args.sizes.partition("-")
    policy = load_lifted_policy(args.rules)
    scratch = FromScratch(policy.classifiers)
    rng = np.random.default_rng(args.seed)
    for n in range(int(first), int(last or first) + 1):
        t0, solved = time.perf_counter(), 0
        for start, goal in sample_pairs(n, args.pairs, rng):
            got, want = rollout_relational(policy, start, goal), rollout_relational(scratch, start, goal)
            if got != want:
                print(f"n = {n}: plans differ from {start.notation()} to {goal.notation()}")
                return 1
            solved += got.reached
        print(f"n = {n}: {args.pairs} pairs, identical plans, {solved} solved, {time.perf_counter() - t0:.1f} s",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
