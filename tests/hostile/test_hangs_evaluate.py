"""Unbounded jobs of ``evaluate`` and ``render --discovery`` (issue 27, class 2).

``evaluate`` listed every episode before the first one ran (``--pairs 100000000000`` at 8
blocks, ``--seeds 1000000000``, ``--pairs all`` at 6 blocks: hundreds of MB and growing, no
episode started), and ``render --discovery`` recorded every frame of as many attempts as
``--transitions`` asked. Both keep one record per item for their report or video, so a
count whose records cannot fit the memory available (``train``'s ``--max-memory`` default)
is now refused at once, in one line naming the count; a count that fits is streamed: its
episodes are drawn a batch at a time, never all listed.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from hostile_cli import csql, digest, environment

REFUSED_WITHIN = 20
"""Seconds a refusal may take: it comes before any work (the command used to run on for minutes)."""
STARTED_WITHIN = 60
"""Seconds until the first batch of a streamed job (about 5 s on a loaded 2-core machine; listing 49.8 M
episodes first took minutes)."""


def names_count(err: str, count: int) -> None:
    """The error line names ``count`` (with or without thousands separators)."""
    assert f"{count:,}" in err or str(count) in err, err


def test_ev_pairs_1e11_n8(work: Path) -> None:
    run = csql(work, "evaluate", "--quiet", "--blocks", "8", "--planner", "gn1", "--pairs", "100000000000",
               "--workers", "1", timeout=REFUSED_WITHIN)
    names_count(run.refused("--pairs"), 100_000_000_000)
    assert digest(work) == {}


def test_ev_seeds_1e9_n3(work: Path) -> None:
    run = csql(work, "evaluate", "--quiet", "--blocks", "3", "--seeds", "1000000000", "--workers", "1",
               timeout=REFUSED_WITHIN)
    names_count(run.refused("--seeds"), 462 * 1_000_000_000)  # 462 pairs of 3 blocks, each 10^9 times
    assert digest(work) == {}


def test_ev_pairs_all_n6(work: Path) -> None:
    from csql_sim.jobs.job_memory import EPISODE_BYTES
    from csql_sim.learners.training.costs import PROCESS_BYTES, available_memory

    episodes = 7057 * 7056  # every ordered pair of the 7057 states of 6 blocks
    if PROCESS_BYTES + episodes * EPISODE_BYTES <= available_memory():
        pytest.skip("this machine has room for every summary: the job streams (test_a_job_that_fits_streams)")
    run = csql(work, "evaluate", "--quiet", "--blocks", "6", "--pairs", "all", "--workers", "1",
               timeout=REFUSED_WITHIN)
    names_count(run.refused(), episodes)
    assert digest(work) == {}


def test_y_render_discovery_memory_60s(work: Path) -> None:
    run = csql(work, "render", "--discovery", "--transitions", "1000000000", "--out", "d.gif", "--quiet",
               "--width", "32", "--height", "32", timeout=REFUSED_WITHIN)
    names_count(run.refused("--transitions"), 1_000_000_000)
    assert digest(work) == {}  # no video, no sidecar


STREAM = """
import json, sys, time, tracemalloc
import csql_sim.jobs.evaluate as ev
import csql_sim.jobs.job_memory as jm

jm.available_memory = lambda: 1 << 62  # a machine with room for every summary: the job is not refused


class Started(Exception):
    pass


def first_batch(fn, batch, *args, **kwargs):  # the first episodes handed to the workers: stop there
    raise Started(len(batch), batch[0].seed)


ev.map_tasks = first_batch
tracemalloc.start()
began = time.perf_counter()
try:
    ev.evaluate(progress=False, **json.loads(sys.argv[1]))
except Started as started:
    size, seed = started.args
    print(json.dumps({"batch": size, "first_seed": seed, "seconds": time.perf_counter() - began,
                      "peak": tracemalloc.get_traced_memory()[1], "limit": ev.BATCH_EPISODES}))
"""


@pytest.mark.parametrize("job", [
    {"n": 8, "pairs": 100_000_000_000, "planner": "gn1", "workers": 1},
    {"n": 3, "seeds": 1_000_000_000, "workers": 1},
    {"n": 6, "pairs": "all", "workers": 1},
], ids=["pairs-1e11-n8", "seeds-1e9-n3", "pairs-all-n6"])
def test_a_job_that_fits_streams(work: Path, job: dict) -> None:
    """With memory to spare, the same jobs start their first episode at once, the specs not listed."""
    done = subprocess.run([sys.executable, "-c", STREAM, json.dumps(job)], cwd=work, env=environment(work),
                          capture_output=True, text=True, timeout=STARTED_WITHIN)
    assert done.returncode == 0 and done.stdout, done.stderr
    started = json.loads(done.stdout)
    assert started["first_seed"] == 0 and 1 <= started["batch"] <= started["limit"]
    assert started["peak"] < 64 << 20, started  # bytes held by Python while the first batch was drawn


def test_batches_and_workers_do_not_change_the_report(monkeypatch: pytest.MonkeyPatch) -> None:
    """The same episodes in the same order, whatever the batch size and the number of workers."""
    import csql_sim.jobs.evaluate as ev

    whole = ev.evaluate(3, pairs=2, seeds=2, perturb=True, seed=5, workers=1, progress=False).to_dict()
    monkeypatch.setattr(ev, "BATCH_EPISODES", 3)  # 4 episodes: a batch of 3, then one
    batched = ev.evaluate(3, pairs=2, seeds=2, perturb=True, seed=5, workers=2, progress=False).to_dict()
    assert batched["runs"] == whole["runs"] and len(whole["runs"]) == 4
    assert [(r["start"], r["goal"], r["seed"]) for r in whole["runs"]] == \
        [(s.start, s.goal, s.seed) for s in ev.make_specs(3, 2, seeds=2, sample_seed=5)]
