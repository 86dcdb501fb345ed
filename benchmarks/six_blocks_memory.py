"""Run a command and report its wall time and the peak resident memory of its whole process tree.

Regenerates docs/results/scaling.md, the wall time and peak memory of a sharded run.

    python benchmarks/six_blocks_memory.py -- csql-sim train --blocks 6 --out rules6

``/usr/bin/time`` reports the largest single process; a sharded run is a driver and its
workers, so this samples the sum of their resident set sizes every 0.2 s (psutil, a
development-only dependency) and prints one JSON line on stderr at the end.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time

import psutil


def tree_rss(proc: psutil.Process) -> int:
    """Resident bytes of ``proc`` and its descendants (those that vanish meanwhile count 0)."""
    total = 0
    for p in [proc, *proc.children(recursive=True)]:
        try:
            total += p.memory_info().rss
        except psutil.Error:
            pass
    return total


def main(argv: list[str]) -> int:
    """Run ``argv`` (after ``--``), sampling its tree; its exit status."""
    command = argv[argv.index("--") + 1:] if "--" in argv else argv
    if not command:
        print("usage: six_blocks_memory.py -- COMMAND ...", file=sys.stderr)
        return 2
    began = time.perf_counter()
    child = subprocess.Popen(command)
    proc, peak = psutil.Process(child.pid), 0
    while child.poll() is None:
        try:
            peak = max(peak, tree_rss(proc))
        except psutil.Error:
            pass
        time.sleep(0.2)
    print(json.dumps({"command": command, "returncode": child.returncode,
                      "wall_seconds": round(time.perf_counter() - began, 1),
                      "peak_tree_rss_gb": round(peak / 2**30, 3)}), file=sys.stderr)
    return child.returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
