"""How many moves a table move of a deadlocked block wastes, by its above-needed, least-stuck and cover atoms.

Regenerates docs/results/features.md and docs/lifted_learning.md, the excess of deadlocked blocks' table moves.

    python benchmarks/features_table_move_excess.py [--blocks 5] [--pairs 20000] [--draw uniform|tall-towers] [--seed 1]
                                        [--by atoms|deadlocked]

For every drawn (start, goal) pair with a deadlock and every move of a misplaced,
deadlocked block to the table, the move's excess is 1 + optimum(after) - optimum(before),
in moves, by the exact optimum (:func:`csql_sim.core.measure.optimum.optimal_moves`, a
yardstick). Grouped by the atoms (above-needed, least-stuck, cover), it shows which table
moves five-block worlds can tell apart: why the lifted learner leaves ``least-stuck`` unread
by default ([lifted rules](docs/lifted.md)).

With ``--by deadlocked``: in the states with a deadlock where no block can go to its goal place,
every table move of a misplaced block not on the table whose goal support is a block, grouped
by ``deadlocked(?x)`` (the table moves that the 4-operator seeds over generated features make
at n = 20, ``docs/results/features.md``).
"""

from __future__ import annotations

import argparse
from collections import defaultdict

import numpy as np

from csql_sim.core.measure.optimum import optimal_moves
from csql_sim.core.model.task_draws import tall_towers
from csql_sim.core.state.atom_names import ATOMS
from csql_sim.core.state.move_relations import MoveRelations
from csql_sim.core.state.moves import Move, after
from csql_sim.core.state.state import State
from csql_sim.core.state.state_count import sample_hand_empty
from csql_sim.core.state.world import TABLE

GROUP = tuple(ATOMS.index(a) for a in ("above-needed(?x)", "least-stuck(?x)", "cover(?x)"))
DEAD = ATOMS.index("deadlocked(?x)")


def stuck_table_moves(rel: MoveRelations, start: State, goal: State) -> list[tuple[Move, int]]:
    """With no move to a goal place: each table move of a misplaced block off the table whose goal
    support is a block, with ``deadlocked(?x)``; none when some block can go to its goal place."""
    candidates = rel.candidates()
    if any(all(bits[:3]) for _, bits in candidates):  # misplaced, goal-on, ready: a goal move
        return []
    return [(m, bits[DEAD]) for m, bits in candidates
            if m.onto == TABLE and bits[0] and start.support[m.block] != TABLE and goal.support[m.block] != TABLE]


def excesses(n: int, pairs: int, draw: str, seed: int, by: str = "atoms"
             ) -> tuple[int, dict[tuple[int, ...], list[int]]]:
    """The deadlocked pairs drawn and the table moves' excesses, by (above-needed, least-stuck, cover) or ``by``."""
    rng = np.random.default_rng(seed)
    sample = (lambda: tall_towers(n, rng)) if draw == "tall-towers" else (lambda: sample_hand_empty(n, rng))
    out: dict[tuple[int, ...], list[int]] = defaultdict(list)
    stuck = 0
    for _ in range(pairs):
        start, goal = sample(), sample()
        rel = MoveRelations(start, goal)
        if not rel.stuck:
            continue
        stuck += 1
        if by == "deadlocked":
            found = [((dead,), move) for move, dead in stuck_table_moves(rel, start, goal)]
        else:
            found = [(tuple(bits[i] for i in GROUP), move) for move, bits in rel.candidates()
                     if move.onto == TABLE and bits[DEAD]]
        best = optimal_moves(start, goal) if found else 0
        for key, move in found:
            out[key].append(1 + optimal_moves(after(start, move), goal) - best)
    return stuck, out


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--blocks", type=int, default=5)
    parser.add_argument("--pairs", type=int, default=20000)
    parser.add_argument("--draw", choices=("uniform", "tall-towers"), default="uniform")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--by", choices=("atoms", "deadlocked"), default="atoms")
    args = parser.parse_args()
    stuck, out = excesses(args.blocks, args.pairs, args.draw, args.seed, args.by)
    print(f"{args.pairs} {args.draw} pairs of {args.blocks} blocks, {stuck} with a deadlock")
    head = "above-needed | least-stuck | cover" if args.by == "atoms" else "deadlocked"
    print(f"| {head} | table moves | wasted (excess >= 1) | mean excess |")
    print("|" + "---|" * (head.count("|") + 4))
    for key in sorted(out):
        v = np.array(out[key])
        print(f"| {' | '.join(map(str, key))} | {len(v)} | {int((v > 0).sum())} ({100 * (v > 0).mean():.1f}%) | "
              f"{v.mean():.3f} |")


if __name__ == "__main__":
    main()
