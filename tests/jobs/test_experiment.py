import csv
import io

import numpy as np

from csql_sim.jobs.experiment import CSV_COLUMNS, csv_text, run_experiment, summary_lines, write_csv


def test_results_do_not_depend_on_worker_count():
    one = run_experiment(["cs-ql", "cs-bb-rw"], cycles=3, trials=100, seed=5, workers=1)
    two = run_experiment(["cs-ql", "cs-bb-rw"], cycles=3, trials=100, seed=5, workers=2)
    assert csv_text(one) == csv_text(two)
    other = run_experiment(["cs-ql"], cycles=3, trials=100, seed=6, workers=1)
    assert not np.array_equal(other.methods[0].steps, one.methods[0].steps)


def test_csv_columns_rows_and_statistics(tmp_path):
    result = run_experiment(["lt-ql", "cs-ql"], cycles=4, trials=150, seed=1, workers=1)
    path = write_csv(tmp_path / "out" / "figure7.csv", result)
    rows = list(csv.DictReader(io.StringIO(path.read_text())))
    assert tuple(rows[0]) == CSV_COLUMNS
    assert [(r["method"], int(r["trial"])) for r in rows] == [
        (m, t) for m in ("lt-ql", "cs-ql") for t in (0, 50, 100, 150)
    ]
    cs = result.methods[1]
    assert cs.steps.shape == (4, 4)
    assert float(rows[4]["steps_mean"]) == np.float64(f"{cs.steps[:, 0].mean():.6g}")
    assert float(rows[4]["steps_std"]) == np.float64(f"{cs.steps[:, 0].std():.6g}")
    assert all(float(r["steps_mean"]) >= 8 for r in rows)  # never below the optimum


def test_cs_ql_learns_the_test_task_and_summary_names_it():
    result = run_experiment(["cs-ql"], cycles=4, trials=1000, seed=0, workers=1)
    method = result.methods[0]
    assert result.optimal == 8
    assert method.steps_mean[0] > 50 and method.steps_mean[-1] == 8
    first = method.first_optimal(8)
    assert first is not None and 0 < first <= 1000
    assert f"trial {first:>5}" in summary_lines(result)[1]
    assert summary_lines(result)[0].startswith("test task CBA -> BAC (3 blocks), optimum: 8 steps")


def test_figure7_png_has_std_bands_and_a_labelled_optimum(tmp_path):
    from csql_sim.jobs.experiment import figure7, write_png

    result = run_experiment(["cs-ql", "lt-ql"], cycles=3, trials=100, seed=0, workers=1)
    assert write_png(tmp_path / "f.png", result).read_bytes()[:4] == b"\x89PNG"
    steps_ax, value_ax = figure7(result).axes
    for ax, data in ((steps_ax, "steps"), (value_ax, "values")):
        bands = ax.collections
        assert len(bands) == 2  # one band per method
        for band, method in zip(bands, result.methods, strict=True):
            top = band.get_paths()[0].vertices[:, 1].max()
            values = getattr(method, data)
            assert abs(top - (values.mean(axis=0) + values.std(axis=0)).max()) < 1e-9
    labels = [line.get_label() for line in steps_ax.lines]
    assert "optimum: 8 steps" in labels
