"""Ray addresses checked before ``ray.init``: one line, within seconds, on one that cannot work.

``ray.init`` itself waits minutes on an address that accepts connections but is no Ray
cluster, printing a warning a second, and names the Ray Client's install in Ray's words.
"""

from __future__ import annotations

import importlib.util
import os
import socket
import subprocess

from csql_sim.infra.errors import CsqlError
from csql_sim.infra.workers import python_command

CONNECT_TIMEOUT = 5.0  # seconds a Ray address has to accept a connection
GCS_PROBE_SECONDS = 15.0  # seconds a cluster's GCS has to tell its id (a Python start and Ray's import included)
RAY_CLIENT_PORT = 10001  # the port of a ray:// address that names none


def check_ray_address(address: str) -> None:
    """Fail fast, in one line, on a Ray address that cannot work.

    A ``ray://`` address needs the Ray Client (``pip install "ray[client]"``). Any address
    must accept a TCP connection within :data:`CONNECT_TIMEOUT` seconds, and a cluster
    address's GCS must tell its cluster id within :data:`GCS_PROBE_SECONDS` (asked by a
    child process, killed after that): ``ray.init`` itself waits minutes on an address
    that accepts connections but is no Ray cluster, printing a warning a second.

    Raises:
        CsqlError: naming the address and the problem.
    """
    client = address.startswith("ray://")
    if client and importlib.util.find_spec("grpc") is None:
        raise CsqlError(f'--address {address}: a ray:// address needs the Ray Client: pip install "ray[client]"')
    try:
        endpoint = _endpoint(address)
    except ConnectionError as exc:  # "auto" with no cluster to find
        raise CsqlError(f"cannot start Ray at {address}: {' '.join(str(exc).split())}") from None
    except ValueError as exc:
        raise CsqlError(f"--address {address!r}: not a Ray address (auto, host:port or ray://host:port): "
                        f"{' '.join(str(exc).split())}") from None
    if endpoint is None:
        return
    where = f"[{endpoint[0]}]:{endpoint[1]}" if ":" in endpoint[0] else f"{endpoint[0]}:{endpoint[1]}"
    try:
        socket.create_connection(endpoint, timeout=CONNECT_TIMEOUT).close()
    except OSError as exc:
        reason = "no answer" if isinstance(exc, TimeoutError) else exc.strerror or type(exc).__name__
        raise CsqlError(f"cannot reach Ray at {address} ({where}: {reason} within {CONNECT_TIMEOUT:g} s); "
                        f"is the cluster running?") from None
    if not client:
        _probe_gcs(address, where)


def _probe_gcs(address: str, where: str) -> None:
    """Ask the GCS at ``where`` for its cluster id in a child process that dies with us; one line if it cannot."""
    code = ("import sys; from csql_sim.infra.workers import die_with_parent; die_with_parent(int(sys.argv[2])); "
            "from ray._raylet import GcsClient; GcsClient(address=sys.argv[1]).cluster_id")
    argv, env = python_command(code, where, str(os.getpid()))
    try:
        probe = subprocess.run(argv, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                               timeout=GCS_PROBE_SECONDS)
    except subprocess.TimeoutExpired:
        raise CsqlError(f"cannot start Ray at {address}: {where} accepts connections, but no Ray cluster answered "
                        f"within {GCS_PROBE_SECONDS:g} s; is it the right address?") from None
    if probe.returncode != 0:
        last = next((line for line in reversed(probe.stderr.splitlines()) if line.strip()), "no reason given")
        raise CsqlError(f"cannot start Ray at {address}: {where} is no Ray cluster ({' '.join(last.split())[:200]})")


def _endpoint(address: str) -> tuple[str, int] | None:
    """The host and port a Ray address connects to first, resolved as ``ray.init`` does.

    Raises:
        ValueError: not an address.
        ConnectionError: ``"auto"`` finds no cluster.
    """
    if address.startswith("ray://"):
        where = address[len("ray://"):].split("/")[0]
        _, colon, port = where.rpartition(":")
        found: str | None = where if colon and "]" not in port else f"{where}:{RAY_CLIENT_PORT}"  # [::1] has no port
    elif address.rpartition(":")[0].strip("[]") in ("localhost", "::1") or address.startswith("127."):
        found = address  # loopback, probed where it is: Ray would put the node's own address in its place
    else:
        from ray._private.services import canonicalize_bootstrap_address  # what ray.init resolves

        found = canonicalize_bootstrap_address(address)
    if found is None:
        return None
    host, _, port = found.rpartition(":")
    if not host or not port.isdigit():
        raise ValueError(f"no port in {found!r}")
    return host.strip("[]"), int(port)
