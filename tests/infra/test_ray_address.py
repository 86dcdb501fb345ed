"""A Ray address that cannot work fails at once, in one line (found by a hostile-input sweep).

An address that accepts connections but is no Ray cluster printed a warning a second for
20 s; ``ray://`` asked for ``ray[client]`` in Ray's words.
"""

import contextlib
import importlib.util
import socket
import subprocess
import sys
import threading

import pytest

from csql_sim.cli import main
from csql_sim.infra import ray_address
from csql_sim.infra.errors import CsqlError

HANG_GUARD = 60.0  # seconds; only against a hang
needs_ray = pytest.mark.skipif(importlib.util.find_spec("ray") is None, reason="the ray extra is not installed")


def run_cli(*argv: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "csql_sim", *argv], capture_output=True, text=True,
                          timeout=HANG_GUARD)


@needs_ray
def test_ray_client_address_without_the_client_extra_names_the_install(capsys, monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "grpc" else real(name, *a))
    assert main(["evaluate", "--backend", "ray", "--address", "ray://127.0.0.1:10001", "--pairs", "1", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and 'pip install "ray[client]"' in err and "ray://127.0.0.1:10001" in err


@needs_ray
@pytest.mark.parametrize("address", ["nonsense", "host:port", "ray://head:http"])
def test_malformed_addresses_are_one_line(address):
    with pytest.raises(CsqlError, match="address"):
        ray_address.check_ray_address(address)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@needs_ray
def test_an_address_nobody_listens_on_fails_in_one_line():
    out = run_cli("evaluate", "--backend", "ray", "--address", f"127.0.0.1:{_free_port()}", "--pairs", "1", "--quiet")
    assert out.returncode == 2 and out.stdout == ""
    assert len(out.stderr.splitlines()) == 1 and "cannot reach Ray" in out.stderr


@needs_ray
def test_an_address_that_answers_but_is_no_ray_cluster_fails_in_one_line(capfd, monkeypatch):
    """Something accepts connections and says nothing: Ray itself would wait minutes, warning every second."""
    monkeypatch.setattr(ray_address, "GCS_PROBE_SECONDS", 3.0)
    server = socket.create_server(("", 0))  # every interface: for 127.0.0.1 Ray dials the node's own address
    port = server.getsockname()[1]
    stop = threading.Event()

    def accept():
        server.settimeout(0.2)
        kept = []
        while not stop.is_set():
            with contextlib.suppress(OSError):
                kept.append(server.accept()[0])  # accept and say nothing
        for conn in kept:
            conn.close()

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    try:
        status = main(["evaluate", "--backend", "ray", "--address", f"127.0.0.1:{port}", "--pairs", "1", "--quiet"])
    finally:
        stop.set()
        thread.join()
        server.close()
    out, err = capfd.readouterr()  # file descriptors 1 and 2: Ray's C++ side writes there
    assert status == 2 and out == ""
    assert len(err.splitlines()) == 1 and f"127.0.0.1:{port}" in err and "no Ray cluster" in err, err
