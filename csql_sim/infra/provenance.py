"""Provenance: what every output file records about the run that made it.

A provenance record names the package and version and every parameter in force, so a
rule file, CSV, JSON report or video can be reproduced from it.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
import sys
from pathlib import Path
from typing import Any

from csql_sim import __version__

PACKAGE = "csql-sim"


def file_sha256(path: str | os.PathLike) -> str:
    """The hex SHA-256 of a file's bytes."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def plain(value: Any) -> Any:
    """``value`` as JSON/YAML-safe data (dataclasses to dicts, paths to strings, tuples to lists)."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if hasattr(value, "item") and callable(value.item):  # numpy scalars
        return value.item()
    return value


def provenance(**parameters: Any) -> dict[str, Any]:
    """A provenance record: package, version, Python and every parameter given.

    Args:
        **parameters: the parameters in force (dataclasses and paths are converted).
    """
    return {
        "package": PACKAGE,
        "version": __version__,
        "python": ".".join(str(v) for v in sys.version_info[:3]),
        "parameters": plain(parameters),
    }


def rules_source(path: str | os.PathLike | None) -> dict[str, Any]:
    """The rule file a run used, with its SHA-256 (``{"file": None}`` for the BFS planner)."""
    if path is None:
        return {"file": None, "sha256": None}
    if Path(path).is_dir():  # a sharded rule base: its manifest holds every shard's SHA-256
        return {"file": os.fspath(Path(path)), "sha256": file_sha256(Path(path) / "manifest.json"),
                "sha256_of": "manifest.json"}
    return {"file": os.fspath(Path(path)), "sha256": file_sha256(path)}
