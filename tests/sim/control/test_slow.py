import os

import pytest

from csql_sim.core.state.notation import parse_config
from csql_sim.jobs.evaluate import evaluate
from csql_sim.sim.control.executor import run_physical_episode


@pytest.mark.slow
def test_all_462_pairs_succeed():
    report = evaluate(3, pairs="all", workers=os.cpu_count(), progress=False)
    assert report.episodes == 462
    assert report.success_rate == 1.0, report.failures
    assert report.mean_sim_seconds_per_action <= 1.0


@pytest.mark.slow
def test_all_462_pairs_with_perturbation():
    report = evaluate(3, pairs="all", perturb=True, workers=os.cpu_count(), progress=False)
    assert report.success_rate >= 0.99, report.failures


# the eleven failures of `evaluate --blocks 4 --pairs 100 --perturb --perception camera` with the
# segmentation-id camera (most: a held or moving cube reported as "not resting flat anywhere")
CAMERA_FAILURES_BEFORE = [
    ("BA,C,D", "BAC,D", 1919), ("CDBA", "A,CDB", 3975), ("C,DAB", "BCA,D", 5233), ("CAB,D", "BDAC", 6014),
    ("CAB,D", "DAC+B", 6066), ("ABD,C", "DCAB", 7122), ("ACBD", "ACDB", 8357), ("CBAD", "BCA,D", 8953),
    ("A,BC+D", "B,DA+C", 9997), ("BAC+D", "A,B,C+D", 14457), ("ACD+B", "A,BD+C", 14964), ("B,CDA", "AD,CB", 1159),
]


@pytest.mark.slow
@pytest.mark.parametrize(("start", "goal", "seed"), CAMERA_FAILURES_BEFORE, ids=lambda v: str(v))
def test_former_camera_failures_succeed(start, goal, seed):
    r = run_physical_episode(parse_config(start), parse_config(goal), seed=seed, perturb=True, perception="camera")
    assert r.success, r.reason


@pytest.mark.slow
@pytest.mark.parametrize("n", [3, 4, 5])
def test_perturbed_camera_sample(n):
    report = evaluate(n, pairs=6, perturb=True, perception="camera", workers=os.cpu_count(), progress=False,
                      camera_noise=(0.001, 3.0))
    assert report.episodes == 6
    assert report.success_rate == 1.0, report.failures
