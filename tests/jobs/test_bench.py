"""The benchmark times each method's two engines on the same trajectory (no timing is asserted)."""

import json

from csql_sim.cli import main
from csql_sim.jobs.bench import bench


def test_both_methods_engines_run_the_same_steps():
    r = bench(trials=60, seed=2, repeats=1)
    assert r.identical and r.lt_identical
    assert r.reference.steps == r.fast.steps == r.plain.steps > 60
    assert r.lt_reference.steps == r.lt_fast.steps > r.reference.steps  # LT-QL also tries the illegal actions
    assert r.lt_ratio == r.lt_fast.rate / r.lt_reference.rate > 0


def test_cli_reports_lt_ql_engines_and_their_ratio(capsys, tmp_path):
    report = tmp_path / "bench.json"
    assert main(["bench", "--trials", "30", "--repeats", "1", "--json", str(report)]) == 0
    doc = json.loads(report.read_text())
    assert doc["lt_identical"] is True and doc["lt_ratio"] > 0
    assert doc["lt_fast"]["steps"] == doc["lt_reference"]["steps"] > 30
    assert main(["bench", "--trials", "30", "--repeats", "1"]) == 0
    assert "LT-QL's two engines: identical trajectories (same rule file): yes" in capsys.readouterr().out
