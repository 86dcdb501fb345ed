"""Which generated literals tell a deadlocked block's table move from one of a block not deadlocked.

Regenerates docs/results/features.md, the literals that separate deadlocked table moves.

    python benchmarks/features_separating_literals.py [--sizes 5,12,20] [--states 150] [--top 15]

Builds the 4-operator feature space as the learner does (K = 8, pruned on 200 sampled pairs of
five blocks, 40 goals, ``np.random.default_rng(0)``). Then, for each size, draws random pairs
(seeded by the size) until ``--states`` states have a deadlock, no move to a goal place and a
table move of a misplaced block that is not deadlocked (goal support a block); every such
table move of a misplaced block whose goal support is a block is labelled by ``deadlocked(?x)``
(the yardstick relation). Prints the literals whose share of 1s differs most between the two
labels at every size (the least difference over the sizes, same sign), with the shares
(deadlocked / not) per size. The figures describe the feature space; no policy uses them.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
from features_table_move_excess import stuck_table_moves  # the script beside this one

from csql_sim.core.features.formulation import load_formulation
from csql_sim.core.features.move_features import literal_values
from csql_sim.core.state.move_relations import MoveRelations
from csql_sim.core.state.state_count import sample_hand_empty
from csql_sim.learners.lifted.features import build_space


def examples(n: int, states: int) -> list[tuple]:
    """(state, goal, table moves, deadlocked labels) for ``states`` states of ``n`` blocks."""
    rng, out = np.random.default_rng(n), []
    while len(out) < states:
        s, g = sample_hand_empty(n, rng), sample_hand_empty(n, rng)
        rel = MoveRelations(s, g)
        found = stuck_table_moves(rel, s, g) if rel.stuck else []
        if found and not all(dead for _, dead in found):
            out.append((s, g, tuple(m for m, _ in found), [bool(dead) for _, dead in found]))
    return out


def main(argv: list[str] | None = None) -> int:
    """Print the literals that separate the two kinds of table move best at every size."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="5,12,20", help="world sizes (default 5,12,20)")
    parser.add_argument("--states", type=int, default=150, help="states per size (default 150)")
    parser.add_argument("--top", type=int, default=15, help="literals printed (default 15)")
    args = parser.parse_args(argv)
    form, rng = load_formulation("4op"), np.random.default_rng(0)
    goals = [sample_hand_empty(5, rng) for _ in range(40)]
    literals = build_space(form, 5, goals, rng, 8, 200).literals
    print(f"{len(literals)} literals", flush=True)
    shares = {}
    for n in (int(x) for x in args.sizes.split(",")):
        rows: dict[bool, list[np.ndarray]] = {True: [], False: []}
        for s, g, table, labels in examples(n, args.states):
            _, values = literal_values(literals, form, s, g, table)
            for v, label in zip(values, labels, strict=True):
                rows[label].append(v)
        shares[n] = (np.mean(rows[True], axis=0), np.mean(rows[False], axis=0))
        print(f"n={n}: {args.states} states, {len(rows[True])} deadlocked and {len(rows[False])} other table moves",
              flush=True)
    gaps = np.stack([not_dead - dead for dead, not_dead in shares.values()])
    score = np.abs(gaps).min(axis=0) * (np.sign(gaps).min(axis=0) == np.sign(gaps).max(axis=0))
    for j in np.argsort(-score)[:args.top]:
        per = " ".join(f"n={n}: {d[j]:.2f}/{o[j]:.2f}" for n, (d, o) in shares.items())
        print(f"{score[j]:.2f}  {per}  {literals[j].words()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
