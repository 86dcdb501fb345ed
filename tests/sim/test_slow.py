import os

import pytest

from csql_sim.evaluate import evaluate


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
