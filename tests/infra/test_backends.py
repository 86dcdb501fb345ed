import math
import os
import subprocess
import time

import pytest

from csql_sim.core.state.notation import parse_config
from csql_sim.infra.backends import Backend, TaskFailure, map_tasks
from csql_sim.infra.errors import CsqlError
from csql_sim.jobs.evaluate import evaluate
from csql_sim.jobs.experiment import csv_text, run_experiment

CONFIGS = ["AB,C", "A?", "CBA", "C,B,A"]  # the second raises WorldError (a CsqlError): a failed task


def check_configs(out):
    """In item order, the failed task in its place."""
    assert len(out) == 4 and [out[k] for k in (0, 2, 3)] == [parse_config(CONFIGS[k]) for k in (0, 2, 3)]
    assert isinstance(out[1], TaskFailure) and out[1].reason.startswith("WorldError: ")


def test_backend_validation():
    with pytest.raises(CsqlError, match="backend must be one of"):
        Backend("dask")
    with pytest.raises(CsqlError, match="--address needs --backend ray"):
        Backend("processes", address="auto")
    with pytest.raises(CsqlError, match="--workers"):
        Backend("processes", workers=0)


@pytest.mark.parametrize("workers", [1, 2])
def test_processes_keep_order_and_report_a_failing_task_in_its_place(workers):
    check_configs(map_tasks(parse_config, CONFIGS, Backend("processes", workers)))


@pytest.mark.parametrize("workers", [1, 2])
def test_a_bug_in_a_task_propagates_instead_of_becoming_a_failure(workers):
    with pytest.raises(TypeError):
        map_tasks(math.sqrt, [4.0, "x", 9.0], Backend("processes", workers))
    with pytest.raises(ValueError) as raised:  # a ValueError that is no CsqlError is a bug too
        map_tasks(math.sqrt, [4.0, -1.0], Backend("processes", workers))
    assert not isinstance(raised.value, CsqlError)


@pytest.mark.parametrize("workers", [1, 2])
def test_a_failing_worker_setup_fails_every_task_but_a_buggy_one_propagates(workers):
    out = map_tasks(math.sqrt, [1.0, 4.0], Backend("processes", workers), setup=parse_config, setup_args=("A?",))
    assert len(out) == 2 and all(isinstance(r, TaskFailure) and "setup" in r.reason for r in out)
    with pytest.raises(TypeError):
        map_tasks(math.sqrt, [1.0, 4.0], Backend("processes", workers), setup=math.sqrt, setup_args=("x",))


_REMEMBERED = []  # what _remember set up last in this process


def _remember(value):
    _REMEMBERED[:] = [value]


def _recall(_item):
    return _REMEMBERED[0]


def test_a_setup_runs_again_after_one_with_other_arguments():
    one = Backend("processes", 1)  # the tasks, and their setup, run in this process
    runs = [map_tasks(_recall, [0, 1], one, setup=_remember, setup_args=(v,)) for v in ("a", "b", "a")]
    assert runs == [["a", "a"], ["b", "b"], ["a", "a"]]


def test_processes_report_a_dead_worker_as_failures():
    out = map_tasks(os._exit, [3, 4], Backend("processes", 2))
    assert len(out) == 2 and all(isinstance(r, TaskFailure) and "died" in r.reason for r in out)


# ------------------------------------------------------------------ Ray (the test extra installs it)


@pytest.fixture(scope="module")
def ray_local():
    """One local Ray instance for this module's tests (map_tasks uses a session it did not open)."""
    ray = pytest.importorskip("ray", reason="the ray extra is not installed")
    ray.init(num_cpus=2, include_dashboard=False, logging_level="ERROR", log_to_driver=False)
    yield ray
    ray.shutdown()


def test_ray_keeps_order_and_reports_a_failing_task_in_its_place(ray_local):
    check_configs(map_tasks(parse_config, CONFIGS, Backend("ray")))
    assert ray_local.is_initialized(), "a session the caller opened must stay open"


def test_a_bug_in_a_ray_task_propagates(ray_local):
    with pytest.raises(TypeError):
        map_tasks(math.sqrt, [4.0, "x", 9.0], Backend("ray"))
    assert ray_local.is_initialized()


def test_a_bug_in_a_ray_task_cancels_the_rest_in_a_session_the_caller_opened(ray_local):
    """Left alone, the first task would hold its CPU for 30 s after map_tasks raised."""
    with pytest.raises(subprocess.CalledProcessError):  # no CsqlError: a bug
        map_tasks(subprocess.check_call, [["sleep", "30"], ["sh", "-c", "sleep 2; exit 3"]], Backend("ray"))
    deadline = time.monotonic() + 20.0  # only against a hang
    while ray_local.available_resources().get("CPU", 0.0) < 2.0:
        assert time.monotonic() < deadline, "the sleeping task was not cancelled"
        time.sleep(0.2)


def test_ray_says_where_it_runs_in_one_line_with_progress(ray_local, capsys):
    assert map_tasks(math.sqrt, [1, 4], Backend("ray"), progress=True) == [1.0, 2.0]
    lines = [line for line in capsys.readouterr().err.replace("\r", "\n").splitlines() if "ray" in line.lower()]
    assert len(lines) == 1 and lines[0].startswith("ray: existing session, 2 CPUs"), lines


def test_ray_reports_a_dead_worker_as_a_failure(ray_local):
    (out,) = map_tasks(os._exit, [3], Backend("ray"))
    assert isinstance(out, TaskFailure) and "died" in out.reason


def test_experiment_on_ray_writes_the_same_csv_as_processes(ray_local):
    kwargs = {"methods": ("cs-bb-bz", "lt-ql"), "cycles": 3, "trials": 150, "seed": 4}
    on_ray = csv_text(run_experiment(**kwargs, backend=Backend("ray")))
    in_pool = csv_text(run_experiment(**kwargs, workers=2))
    assert on_ray == in_pool
    assert len(on_ray.splitlines()) == 1 + 2 * 4  # header, then trials 0, 50, 100, 150 per method


def test_evaluate_on_ray_gives_the_same_report_as_processes(ray_local):
    kwargs = {"pairs": 3, "seeds": 2, "perturb": True, "progress": False}
    on_ray = evaluate(3, **kwargs, backend=Backend("ray"))
    in_pool = evaluate(3, **kwargs, workers=2)
    assert (on_ray.config["backend"], in_pool.config["backend"]) == ("ray", "processes")
    assert {**on_ray.to_dict(), "config": None} == {**in_pool.to_dict(), "config": None}
    assert on_ray.episodes == 6 and on_ray.text() == in_pool.text()


def test_scaling_on_ray_gives_the_same_trials_and_steps(ray_local):
    from csql_sim.jobs.scaling import run_scaling

    kwargs = {"blocks": [2, 3], "methods": ["lt-ql", "cs-ql"], "seed": 1, "max_trials": 400}
    on_ray = run_scaling(**kwargs, backend=Backend("ray"))
    in_process = run_scaling(**kwargs)
    assert [(r.method, r.blocks, r.trials, r.steps, r.optimal_pairs) for r in on_ray] == [
        (r.method, r.blocks, r.trials, r.steps, r.optimal_pairs) for r in in_process]
    assert [r.blocks for r in on_ray] == [2, 2, 3, 3]
