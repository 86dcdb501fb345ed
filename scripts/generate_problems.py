"""Write random blocks-world problems in the IPC format (and BFS plans for up to six blocks).

    python scripts/generate_problems.py OUTDIR --count K --blocks N[,N...] --seed S [--no-plans]

OUTDIR gets ``domain.pddl`` (the 4-operator IPC blocks domain), ``blocks<N>-<k>.pddl``
and, for N <= 6, the optimal plan ``blocks<N>-<k>.plan`` in Fast Downward's format. The
test set in tests/data/problems is ``--count 2 --blocks 3,4,5 --seed 0``. How problems
are drawn: ``csql_sim/jobs/problems.py``.
"""

from __future__ import annotations

import argparse
import sys

from csql_sim.infra.errors import CsqlError
from csql_sim.jobs.problems import write_problem_set


def sizes(text: str) -> list[int]:
    try:
        return [int(part) for part in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected N or N,N,..., got {text!r}") from None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", help="output folder")
    parser.add_argument("--count", type=int, default=1, help="problems per size (default 1)")
    parser.add_argument("--blocks", type=sizes, default=[3], help="objects per problem, 3..10; a list: 3,4,5")
    parser.add_argument("--seed", type=int, default=0, help="seed of the one generator (default 0)")
    parser.add_argument("--no-plans", action="store_true", help="write problems only")
    args = parser.parse_args(argv)
    try:
        written = write_problem_set(args.out, args.count, args.blocks, args.seed, plans=not args.no_plans)
    except CsqlError as exc:
        print(f"generate_problems: error: {exc}", file=sys.stderr)
        return 2
    print(f"wrote {len(written)} files to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
