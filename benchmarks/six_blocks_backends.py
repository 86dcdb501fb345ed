"""Ray's start-up overhead against the local process pool, on the same tasks.

Regenerates docs/results/scaling.md, Ray's start-up overhead against the process pool.

Times, for each backend, a small ``evaluate`` (physical episodes) and a small
``experiment`` (Figure 7 cycles), each from a cold start (Ray: a fresh local instance,
started and shut down inside the call); checks the results are identical; and times a
bare Ray start and shutdown.
Usage: python benchmarks/six_blocks_backends.py [--workers W] [--pairs K] [--cycles C]
"""

from __future__ import annotations

import argparse
import os
import time

from csql_sim.infra.backends import Backend
from csql_sim.infra.ray_session import ray_session
from csql_sim.jobs.evaluate import evaluate
from csql_sim.jobs.experiment import csv_text, run_experiment


def timed(fn, *args, **kwargs):  # noqa: ANN001, ANN201
    t = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - t


def bare_ray(workers: int) -> tuple[float, float]:
    """Seconds to start a local Ray instance, and to shut it down."""
    t = time.perf_counter()
    with ray_session(None, workers, announce=False):
        ready = time.perf_counter()
    return ready - t, time.perf_counter() - ready


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--pairs", type=int, default=20)
    parser.add_argument("--cycles", type=int, default=10)
    args = parser.parse_args()
    w = args.workers
    start, stop = bare_ray(w)
    print(f"bare local Ray instance ({w} CPUs): start {start:.1f} s, shutdown {stop:.1f} s")
    for kind in ("processes", "ray"):
        report, wall = timed(evaluate, 3, pairs=args.pairs, progress=False, backend=Backend(kind, w))
        print(f"evaluate --pairs {args.pairs} ({report.episodes} episodes), {kind:<9}: {wall:6.1f} s wall")
        if kind == "processes":
            first = report
        else:
            same = {**report.to_dict(), "config": None} == {**first.to_dict(), "config": None}
            assert same, "the Ray report differs from the process pool's"
    for kind in ("processes", "ray"):
        result, wall = timed(run_experiment, cycles=args.cycles, trials=2500, backend=Backend(kind, w))
        print(f"experiment --cycles {args.cycles} (4 methods x 2500 trials), {kind:<9}: {wall:6.1f} s wall")
        if kind == "processes":
            first_csv = csv_text(result)
        else:
            assert csv_text(result) == first_csv, "the Ray CSV differs from the process pool's"
    print("results identical on both backends")


if __name__ == "__main__":
    main()
