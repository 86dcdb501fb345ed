"""Writes that fail at the end, stdout that cannot be written, SIGTERM and SIGKILL mid-write.

These run ``python -m csql_sim`` in a subprocess: under a file-size limit (``ulimit -f``,
with SIGXFSZ ignored so that a write fails with EFBIG), with stdout on ``/dev/full``, or
killed by a signal. A failure is one stderr line naming the file, with no temporary file
or truncated copy left anywhere (items 3 and 4 of the sweep).
"""

import json
import os
import resource
import signal
import subprocess
import sys
import time

import pytest

LIMIT_BYTES = 20 * 1024  # ulimit -f 20


def limited():
    """preexec_fn: at most LIMIT_BYTES per file, and a write past it fails instead of killing."""
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (LIMIT_BYTES, LIMIT_BYTES))


def env_with_tmp(tmp_path, **extra):
    """The child's environment: its temporary folder is ours to inspect, no bytecode is written."""
    tmp = tmp_path / "tmp"
    tmp.mkdir(exist_ok=True)
    return {**os.environ, "TMPDIR": str(tmp), "PYTHONDONTWRITEBYTECODE": "1", **extra}


def csql(tmp_path, *argv, limit=False, stdout=subprocess.PIPE, env=None, timeout=300):
    work = tmp_path / "work"
    work.mkdir(exist_ok=True)
    return subprocess.run([sys.executable, "-m", "csql_sim", *map(str, argv)], cwd=work, stdout=stdout,
                          stderr=subprocess.PIPE, text=True, env=env or env_with_tmp(tmp_path),
                          preexec_fn=limited if limit else None, timeout=timeout)


def one_line(result, *names):
    err = result.stderr
    assert err.count("\n") == 1 and err.startswith("csql-sim"), err
    assert "Traceback" not in err
    for name in names:
        assert name in err, err
    return err


def names(folder):
    return sorted(p.name for p in folder.iterdir())


# ------------------------------------------------------------------ 3. write failures at the end
@pytest.mark.parametrize("argv, target, written", [
    (["plan", "--pairs", "all", "--json", "big.json"], "big.json", []),
    (["train", "--trials", "20", "--out", "r.yaml"], "r.yaml", []),
    (["scaling", "--blocks", "2,3", "--max-trials", "20", "--out", "."], "scaling.png",
     ["scaling.csv", "scaling.json"]),
])
def test_a_write_past_the_file_size_limit_is_one_line_and_leaves_nothing(tmp_path, argv, target, written):
    result = csql(tmp_path, *argv, "--quiet", limit=True)
    assert result.returncode == 2
    one_line(result, target)
    assert names(tmp_path / "work") == written  # the files that fit; no temporary file, no truncated one
    assert names(tmp_path / "tmp") == []  # no truncated copy "kept" either


def test_evaluate_plot_past_the_file_size_limit(tmp_path):
    result = csql(tmp_path, "evaluate", "--pairs", "1", "--workers", "1", "--plot", "e.png", "--quiet", limit=True)
    assert result.returncode == 2
    one_line(result, "e.png")
    assert names(tmp_path / "work") == [] and names(tmp_path / "tmp") == []


@pytest.mark.parametrize("argv", [["states"], ["plan", "--start", "CBA", "--goal", "BAC", "--json"],
                                  ["plan", "--pairs", "all", "--json"]])
def test_stdout_on_a_full_device_is_one_line(tmp_path, argv):
    with open("/dev/full", "w") as full:
        result = csql(tmp_path, *argv, stdout=full)
    assert result.returncode == 2
    one_line(result, "standard output")


def test_a_name_stdout_cannot_encode_is_escaped_not_a_traceback(tmp_path):
    ascii_env = env_with_tmp(tmp_path, PYTHONIOENCODING="ascii")
    result = csql(tmp_path, "states", "--json", "r\u00e9sum\u00e9.json", env=ascii_env)
    assert result.returncode == 0 and "Traceback" not in result.stderr, result.stderr
    assert names(tmp_path / "work") == ["r\u00e9sum\u00e9.json"]
    result = csql(tmp_path, "pddl", "--out", "d\u00e9", env=ascii_env)  # "wrote d\xe9/domain.pddl" on stdout
    assert result.returncode == 0 and result.stderr == "" and "d\\xe9" in result.stdout


# ------------------------------------------------------------------ 4. temporary files after SIGTERM / SIGKILL
def start_and_wait_for_temp(tmp_path, *argv):
    """Start a command; return it once its temporary output file exists."""
    work = tmp_path / "work"
    work.mkdir(exist_ok=True)
    proc = subprocess.Popen([sys.executable, "-m", "csql_sim", *argv, "--quiet"], cwd=work,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env_with_tmp(tmp_path))
    deadline = time.monotonic() + 120
    while not any(".tmp" in name for name in names(work)):
        assert proc.poll() is None, proc.stderr.read()
        assert time.monotonic() < deadline, "no temporary file appeared"
        time.sleep(0.05)
    time.sleep(0.2)
    return proc, work


def test_sigterm_removes_the_temporary_file(tmp_path):
    proc, work = start_and_wait_for_temp(tmp_path, "plan", "--pairs", "all", "--blocks", "5", "--json", "big.json")
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + signal.SIGTERM
    assert err == "csql-sim: terminated\n"
    assert names(work) == []


def test_sigterm_while_rendering_leaves_no_temporary_file_and_no_warning(tmp_path):
    proc, work = start_and_wait_for_temp(tmp_path, "render", "--start", "CBA", "--goal", "ABC", "--out", "v.mp4",
                                         "--workers", "2")
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + signal.SIGTERM
    assert err == "csql-sim: terminated\n"  # one line: no "leaked semaphore" warning
    assert names(work) == []


def test_the_next_run_removes_what_sigkill_left(tmp_path):
    proc, work = start_and_wait_for_temp(tmp_path, "plan", "--pairs", "all", "--blocks", "5", "--json", "big.json")
    proc.kill()
    proc.communicate(timeout=60)
    (left,) = names(work)
    assert left.startswith(".big.json.csql-sim-") and left.endswith(".tmp.json")  # recognisable
    result = csql(tmp_path, "plan", "--pairs", "3", "--json", "big.json")
    assert result.returncode == 0, result.stderr
    assert names(work) == ["big.json"]


def test_stdout_full_after_the_work_names_the_files_it_kept(tmp_path):
    """A full stdout fails only at the end: the model is written and kept, and the one line says so."""
    with open("/dev/full", "w") as full:
        result = csql(tmp_path, "train-lifted", "--quiet", "--trials", "20", "--sizes", "3", "--goals", "2",
                      "--out", "n.json", stdout=full)
    assert result.returncode == 2
    one_line(result, "standard output", "kept", "n.json")
    assert json.loads((tmp_path / "work" / "n.json").read_text())["format"] == "csql-sim lifted q-classifiers"
