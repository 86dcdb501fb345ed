"""Where a policy's plans waste moves: every move it makes, classed by the state before it.

Regenerates docs/results/features.md, the table of move kinds per policy.

    python benchmarks/features_move_kinds.py [--policy-file FILE ...] [--n 20] [--use 100]

Plans the first ``--use`` benchmark pairs of size ``--n`` (those of ``benchmarks/features_table.py``:
one generator seeded 0 draws 1,000 pairs for n = 6, 7, 8, 10, 15, 20, 26 in turn) with GN1, the
hand ordering and each policy file, and classes each move (a pick and the put after it) by the
yardstick relations of the state before it (:mod:`csql_sim.core.state.goal_relations`):

* ``final``: the block reaches its goal support and is well placed there;
* ``table, deadlocked``: a misplaced, deadlocked block to the table;
* ``table, not deadlocked``: a misplaced block that is not deadlocked, whose goal support is a
  block, to the table (in a state with a deadlock and no move to a goal place it always
  wastes a move; ``docs/results/features.md``);
* ``parked``: a misplaced block onto a block that is not its goal place;
* ``well placed``: a well-placed block moved (a goal that holds a block ends with its pick);
* ``table, on the table``: a block picked from the table and put back there;
* ``put of the block held at the start``: not classed (the deadlock graph needs a hand-empty state).

Prints one line per policy: optimal %, actions over the exact optimum, and the count of each
kind. The figures describe the plans; the policies are not changed by them.
"""

from __future__ import annotations

import argparse
import sys
from collections import Counter

from features_table import BENCH_SIZES, tasks  # the scripts beside this one
from lifted_learning_seeds import hand_ordering

from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.goal_relations import deadlocked, well_placed
from csql_sim.core.state.move_relations import target_goal
from csql_sim.core.state.world import TABLE, State, successor


def benchmark_tasks(n: int, use: int) -> list[tuple[State, State, int]]:
    """The first ``use`` benchmark pairs of size ``n`` with their exact optima (``feature_table.tasks``)."""
    if n not in BENCH_SIZES:
        raise SystemExit(f"move_kinds: --n must be one of {', '.join(map(str, BENCH_SIZES))}")
    rows = tasks(argparse.Namespace(sizes=[n], use=use, tall=[], tall_tasks=0))[f"n={n}"]
    return [(start, goal, best) for start, goal, best, _ in rows]


def kind(before: State, after: State, goal: State, block: int) -> str:
    """The kind of the move of ``block`` from hand-empty ``before`` to hand-empty ``after``."""
    target = target_goal(before, goal)
    placed = well_placed(before, target)
    if placed[block]:
        return "well placed"
    if after.support[block] == target.support[block] and well_placed(after, target)[block]:
        return "final"
    if after.support[block] != TABLE:
        return "parked"
    if before.support[block] == TABLE:
        return "table, on the table"
    return "table, deadlocked" if block in deadlocked(before, target) else "table, not deadlocked"


def classify(policy, pairs: list[tuple[State, State, int]], hand: bool) -> tuple[int, int, Counter, int]:  # noqa: ANN001
    """Optimal plans, actions over the optimum (solved plans), the moves by kind, and the unsolved."""
    kinds: Counter = Counter()
    optimal = over = unsolved = 0
    for start, goal, best in pairs:
        run = rollout_relational(policy, start, goal, hand=hand)
        if not run.reached:
            unsolved += 1
            continue
        optimal += run.length == best
        over += run.length - best
        state, before = start, start
        for action in run.actions:
            if state.held is None:
                before = state
            nxt = successor(state, action)
            if state.held is not None and nxt.held is None:  # a put: the move of the block held
                held_start = before.held is not None  # the start holds it: no pick, no hand-empty state before
                kinds["put of the block held at the start" if held_start else kind(before, nxt, goal, state.held)] += 1
            state = nxt
    return optimal, over, kinds, unsolved


def main(argv: list[str] | None = None) -> int:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--policy-file", action="append", default=[], help="a trained policy file (repeatable)")
    parser.add_argument("--n", type=int, default=20, help="benchmark size (default 20)")
    parser.add_argument("--use", type=int, default=100, help="pairs planned (default 100)")
    args = parser.parse_args(argv)
    pairs = benchmark_tasks(args.n, args.use)
    policies = [("GN1", Gn1Policy()), ("hand ordering", hand_ordering())]
    policies += [(path, load_policy(path)) for path in args.policy_file]
    for name, policy in policies:
        hand = getattr(getattr(policy, "form", None), "hand", True)
        optimal, over, kinds, unsolved = classify(policy, pairs, hand)
        counts = ", ".join(f"{k} {v}" for k, v in sorted(kinds.items()))
        print(f"{name}: {100 * optimal / len(pairs):.0f}% optimal, {over} actions over the optimum, "
              f"{unsolved} unsolved; {counts}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
