"""The CLI on a local Ray instance it starts and stops itself (slow: a Ray start-up each)."""

import pytest

from csql_sim.cli import main


def _ray_processes() -> list[str]:
    import psutil

    names = []
    for child in psutil.Process().children(recursive=True):
        try:
            names.append(child.name())
        except psutil.NoSuchProcess:
            continue
    return [n for n in names if "ray" in n or "gcs_server" in n]


@pytest.fixture
def ray():
    ray = pytest.importorskip("ray", reason="the ray extra is not installed")
    if ray.is_initialized():
        pytest.skip("a Ray session is already open in this process; these tests start their own")
    return ray


@pytest.mark.slow
def test_evaluate_on_ray_prints_the_same_report_and_leaves_no_ray_process(ray, capsys):
    args = ["evaluate", "--pairs", "3", "--seeds", "2", "--perturb", "--workers", "2", "--quiet"]
    status = main(args)
    in_pool = capsys.readouterr().out
    assert main([*args, "--backend", "ray"]) == status
    captured = capsys.readouterr()
    assert captured.out == in_pool and "episodes: 6" in in_pool
    assert captured.err == "", "Ray must stay quiet with --quiet"
    assert not ray.is_initialized()
    assert _ray_processes() == []


@pytest.mark.slow
def test_experiment_on_ray_writes_the_same_csv_and_keeps_stderr_quiet(ray, tmp_path, capsys):
    args = ["experiment", "--methods", "cs-ql", "--cycles", "3", "--trials", "100", "--workers", "2"]
    assert main([*args, "--out", str(tmp_path / "pool")]) == 0
    assert main([*args, "--out", str(tmp_path / "ray"), "--backend", "ray"]) == 0
    captured = capsys.readouterr()
    assert (tmp_path / "ray" / "figure7.csv").read_text() == (tmp_path / "pool" / "figure7.csv").read_text()
    assert captured.err == "", "stderr is not a terminal here: no bar, and nothing from Ray"
    assert "on Ray (a local instance)" in captured.out
    assert not ray.is_initialized()
    assert _ray_processes() == []


def test_address_without_ray_backend_is_one_line_exit_2(capsys):
    assert main(["evaluate", "--pairs", "1", "--address", "auto"]) == 2
    assert capsys.readouterr().err.strip() == "csql-sim evaluate: error: --address needs --backend ray"
