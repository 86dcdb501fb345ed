"""Memory, disk and time of a training job, estimated before any work; refusal when it cannot fit.

:func:`estimate` needs only n, the method, the engine's layout (one engine or shards of
goals) and the workers: the number of states comes from a formula (:func:`state_count`),
not from enumerating them. The per-state and per-pair constants below were measured on
the development machine (2 cores, 24 GB; see the README's "Six blocks" section) and are
extrapolated past 6 blocks by the growth from 5 to 6. :func:`check_fits` refuses, in one
line naming the estimate, the limit and the alternatives, a job whose peak memory exceeds
the memory available (or ``--max-memory``), or whose output exceeds the free disk.
"""

from __future__ import annotations

import os
import shutil
from dataclasses import dataclass
from pathlib import Path

from csql_sim.core.state.state_count import state_count
from csql_sim.core.state.world import MAX_BLOCKS
from csql_sim.infra.errors import CsqlError

GB = 1 << 30
MB = 1 << 20
CANDIDATES = {2: 1.4, 3: 1.82, 4: 2.18, 5: 2.41, 6: 2.63}
"""Mean legal actions (candidates) per state, counted from the R-classifiers (2.63 = 18,552 / 7,057 at n = 6)."""
PAIR_SECONDS = {3: 6.0e-4, 4: 5.8e-5, 5: 2.2e-5}
"""CPU seconds per (start, goal) pair of CS-QL's one engine with its default trials and sweep, measured
(0.3 s, 0.9 s and 16.5 s at n = 3, 4, 5: the trials, a fixed 2,500 or 20,000, weigh more at small n)."""
SHARD_PAIR_SECONDS = {4: 6.0e-5, 5: 1.3e-5, 6: 1.87e-5}
"""The same for sharded training, all shards together (9.6 CPU s for 749,090 pairs at n = 5 in 8 shards,
928.8 CPU s for 49,794,192 at n = 6 in 64)."""
TABULAR_PAIR_SECONDS = {3: 3.0e-4, 4: 2.2e-4, 5: 1.5e-4}
"""The same for the other learners (LT-QL's array engine, 20,000 trials: 112 s at n = 5; the reference
engines of the bucket brigades are slower), measured at n <= 5."""
PROCESS_BYTES = 200 * MB
"""A Python process with numpy, numba and the world loaded."""
SHARD_GOAL_BYTES_PER_STATE = 660
"""A worker's memory per goal of its shard per state (engine arrays, the shard's copy, the count): measured
0.68-0.73 GB for workers of 110 goals at n = 6 (4.7 MB a goal)."""
DRIVER_BYTES_PER_STATE = 25_000
"""The sharded run's driver: the world, its world model and the manifest (0.38 GB measured at n = 6)."""


def _per(table: dict[int, float], n: int) -> float:
    """A measured constant at n, extrapolated geometrically past the table."""
    top = max(table)
    if n <= top:
        return table[max(min(n, top), min(table))]
    return table[top] * (table[top] / table[top - 1]) ** (n - top)


@dataclass(frozen=True)
class Estimate:
    """What a training job will need.

    Attributes:
        n: number of blocks.
        method: the learner.
        shards: shards of goals (1: one engine).
        workers: processes training shards at once.
        states: the number of states.
        pairs: ordered (start, goal) pairs.
        peak_bytes: peak resident memory of all processes together.
        disk_bytes: size of the rule base written.
        seconds: wall time on ``workers`` cores like the development machine's.

    """

    n: int
    method: str
    shards: int
    workers: int
    states: int
    pairs: int
    peak_bytes: int
    disk_bytes: int
    seconds: float
    sharded: bool = False

    def line(self) -> str:
        """The estimate in one line."""
        layout = f"{self.shards} shard(s) on {self.workers} worker(s)" if self.sharded else "one engine"
        return (f"{self.method}, {self.n} blocks ({self.states:,} states, {self.pairs:,} pairs, {layout}): "
                f"about {format_size(self.peak_bytes)} peak memory, {format_size(self.disk_bytes)} written, "
                f"{_duration(self.seconds)}")


def estimate(method: str, n: int, shards: int, workers: int, sharded: bool | None = None) -> Estimate:
    """The memory, disk and time of training ``method`` at n blocks (see the module docstring).

    ``sharded`` (default: ``shards > 1``) says whether the rule base is a sharded directory.
    """
    states = state_count(n)
    pairs = states * (states - 1)
    slots = states * _per(CANDIDATES, n)
    split = sharded or (sharded is None and shards > 1)
    per = (SHARD_PAIR_SECONDS if split else PAIR_SECONDS) if method == "cs-ql" else TABULAR_PAIR_SECONDS
    seconds = pairs * _per(per, n)
    if split:
        goals = -(-states // shards)
        worker = PROCESS_BYTES + goals * states * SHARD_GOAL_BYTES_PER_STATE
        peak = PROCESS_BYTES + states * DRIVER_BYTES_PER_STATE + min(workers, shards) * worker
        disk = pairs * 16 + states * slots * 16
        return Estimate(n, method, shards, workers, states, pairs, int(peak), int(disk),
                        seconds / min(workers, shards), True)
    classifiers = states * slots  # every (state, goal) node's candidates
    width = 2 * n + 6 if n <= 6 else 3 * n + 4  # message characters
    engine = 32 * states * states + 24 * classifiers
    written = classifiers * (2 * width + 1 + 32)  # the npz arrays, built once and copied once
    peak = PROCESS_BYTES + engine + 2 * written
    return Estimate(n, method, 1, 1, states, pairs, int(peak), int(written), seconds)


def available_memory() -> int:
    """Memory available to new work (``MemAvailable``; the physical memory where it cannot be read)."""
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return 1 << 62


def free_disk(path: str | os.PathLike) -> int:
    """Free bytes on the file system that will hold ``path`` (its nearest existing folder)."""
    p = Path(path).absolute()
    while not p.exists() and p != p.parent:
        p = p.parent
    try:
        return shutil.disk_usage(p).free
    except OSError:
        return 1 << 62


def check_fits(est: Estimate, out: str | os.PathLike, max_memory: int | None = None) -> str | None:
    """None when ``est`` fits this machine (or ``max_memory``); otherwise the refusal's one line."""
    limit = max_memory if max_memory is not None else available_memory()
    what = "--max-memory" if max_memory is not None else "memory available"
    alternatives = ("--backend ray --address A (shards on a cluster), more --shards, fewer --workers, "
                    "or a learner that generalizes; --force goes on anyway")
    if est.n > MAX_BLOCKS:
        return (f"{est.line()}; refused: past the {MAX_BLOCKS} blocks whose states this tool enumerates, whatever "
                "the machine. Alternatives: a learner that generalizes (rules that hold for any number of blocks)")
    if est.peak_bytes > limit:
        return f"{est.line()}; refused: over the {format_size(limit)} {what}. Alternatives: {alternatives}"
    disk = free_disk(out)
    if est.disk_bytes > disk:
        return (f"{est.line()}; refused: the rule base would not fit the {format_size(disk)} free on the disk of "
                f"{os.fspath(out)}. Alternatives: {alternatives}")
    return None


def parse_size(text: str) -> int:
    """``--max-memory``: bytes from ``512M``, ``4G``, ``1.5G`` or a plain number of bytes."""
    units = {"K": 1 << 10, "M": MB, "G": GB, "T": 1 << 40}
    t = text.strip().upper().removesuffix("B").removesuffix("I")
    scale = units.get(t[-1:], 1)
    number = t[:-1] if t[-1:] in units else t
    try:
        value = float(number)
    except ValueError:
        raise CsqlError(f"--max-memory: {text!r} is not a size (e.g. 512M, 4G)") from None
    if not value * scale >= 1 << 20 or value * scale > 1 << 62:  # at least a megabyte
        raise CsqlError(f"--max-memory: {text!r} is out of range")
    return int(value * scale)


def format_size(b: float) -> str:
    """Bytes for messages: ``1.7 GB``, ``372.0 TB``, ``12 MB``, ``4 kB``."""
    for unit, scale in (("PB", 1 << 50), ("TB", 1 << 40)):
        if b >= scale:
            return f"{b / scale:,.1f} {unit}"
    if b < MB:
        return f"{b / 1024:.0f} kB"
    return f"{b / GB:.1f} GB" if b >= GB / 10 else f"{b / MB:.0f} MB"


def _duration(s: float) -> str:
    if s < 120:
        return f"{s:.0f} s"
    return f"{s / 60:.0f} min" if s < 7200 else f"{s / 3600:.1f} h"
