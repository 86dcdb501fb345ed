"""The kinds of file csql-sim writes, told from their first bytes: one registry for the readers and the output check.

Every file the tool writes names its format in its first bytes: JSON files start with
``{"format": "csql-sim ..."``, YAML rule bases with ``format: csql-sim rule base``, npz
rule bases carry it in their ``header`` array, a sharded rule base's directory holds a
``manifest.json`` that names it. :func:`sniff` reads that name: the output check
(:mod:`csql_sim.infra.outputs`) decides with it what an existing file is. Loading a policy
tells a rule file's kind from the same names in one place, from one read of the file
(:mod:`csql_sim.core.files.kinds`, with :func:`head_format`).

The formats of trained models are listed in :data:`MODEL_FORMATS`: a model (and every
file inside a sharded model's directory) is never replaced by a report, even with
``--overwrite`` (:func:`model_kind`).
"""

from __future__ import annotations

import os
import re
import stat
import zipfile
from pathlib import Path

HEAD_BYTES = 4096
"""How much of a file is read to recognise it."""

RULE_BASE = "csql-sim rule base"
"""A ground rule base in YAML (:mod:`csql_sim.core.files.rulebase_yaml`)."""
RULE_BASE_NPZ = "csql-sim rule base (npz)"
"""A ground rule base in npz (:mod:`csql_sim.core.files.rulebase_npz`)."""
SHARDS = "csql-sim-shards"
"""A sharded rule base: its manifest and each shard's header (:mod:`csql_sim.core.files.rulebase_shards`)."""
LIFTED_RULES = "csql-sim lifted rules"
"""Lifted R-classifiers (:mod:`csql_sim.core.classifiers.lifted_rule`)."""
LIFTED_Q = "csql-sim lifted q-classifiers"
"""Learned lifted Q-classifiers (:mod:`csql_sim.core.policies.lifted_policy`)."""
TRANSITIONS = "csql-sim transitions"
"""A transition log of rule discovery (:mod:`csql_sim.discovery.transition_log`)."""
MODEL_FORMATS = frozenset({RULE_BASE, RULE_BASE_NPZ, SHARDS, LIFTED_RULES, LIFTED_Q})
"""The formats of trained models and rule files: never replaced by a report."""
SHARD_MANIFEST = "manifest.json"
"""The file that makes a directory a sharded rule base."""
SHARD_MAGIC = b"CSQL-SHARD"
"""The first bytes of each shard file of a sharded rule base."""
MAX_MANIFEST_BYTES = 1 << 26
"""The largest manifest read (64 MiB, as its reader allows)."""

_JSON_FORMAT = re.compile(rb'\A\s*\{\s*"format"\s*:\s*"(csql-sim[^"\\]*)"')
_YAML_FORMAT = re.compile(rb"\A(?:\s*#[^\n]*\n)*\s*format:\s*['\"]?(csql-sim rule base)\b")


def read_head(path: str | os.PathLike) -> bytes | None:
    """The first :data:`HEAD_BYTES` bytes of a regular file, or None (not one, unreadable).

    Opened without blocking, so a pipe or a device is never waited on or read.
    """
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError:
        return None
    try:
        return os.read(fd, HEAD_BYTES) if stat.S_ISREG(os.fstat(fd).st_mode) else None
    except OSError:
        return None
    finally:
        os.close(fd)


def _npz_format(path: Path) -> str | None:
    """:data:`RULE_BASE_NPZ` if a zip file's ``header`` array names it, else None."""
    try:
        with zipfile.ZipFile(path) as archive, archive.open("header.npy") as member:
            header = member.read(1 << 16)
    except (OSError, KeyError, zipfile.BadZipFile, RuntimeError, ValueError):
        return None
    found = any(RULE_BASE.encode(codec) in header for codec in ("utf-32-le", "utf-32-be", "utf-8"))
    return RULE_BASE_NPZ if found else None


def head_format(head: bytes) -> str | None:
    """The format a file's first bytes name (JSON or YAML), or None."""
    found = _JSON_FORMAT.match(head) or _YAML_FORMAT.match(head)
    return found.group(1).decode("utf-8", "replace") if found else None


def sniff(path: str | os.PathLike) -> str | None:
    """The csql-sim format of the file or directory ``path``, from its first bytes; None if it names none.

    A directory is a sharded rule base (:data:`SHARDS`) when its ``manifest.json`` says so;
    a zip file is an npz rule base when its ``header`` array says so.
    """
    target = Path(path)
    if target.is_dir():
        return SHARDS if sniff(target / SHARD_MANIFEST) == SHARDS else None
    head = read_head(target)
    if head is None:
        return None
    if head.startswith(b"PK"):
        return _npz_format(target)
    if head.startswith(SHARD_MAGIC):
        return SHARDS
    if target.name == SHARD_MANIFEST and head.startswith(b"{"):
        return _manifest_format(target)
    return head_format(head)


def _manifest_format(path: Path) -> str | None:
    """:data:`SHARDS` if a manifest names it: its keys are sorted, so ``format`` follows the shard list."""
    marker = b'"format": "' + SHARDS.encode() + b'"'
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError:
        return None
    with os.fdopen(fd, "rb") as fh:
        tail, seen = b"", 0
        while seen < MAX_MANIFEST_BYTES:
            try:
                chunk = fh.read(1 << 20)
            except OSError:
                return None
            if not chunk:
                return None
            if marker in tail + chunk:
                return SHARDS
            tail, seen = chunk[-len(marker):], seen + len(chunk)
    return None


def in_model_folder(path: str | os.PathLike) -> bool:
    """Whether ``path`` lies in a sharded rule base's directory (its manifest, shards, run report)."""
    folder = Path(os.path.realpath(Path(path).parent))
    return sniff(folder / SHARD_MANIFEST) == SHARDS


def model_kind(path: str | os.PathLike) -> str | None:
    """What ``path`` is, if it is a trained model or rule file of any kind, or a file inside a sharded one; else None.

    Returns:
        A phrase for messages: ``"a csql-sim lifted q-classifiers file"``, ``"a file of a
        sharded rule base"``.
    """
    name = sniff(path)
    if name in MODEL_FORMATS:
        return f"a {name} file"
    return "a file of a sharded rule base" if in_model_folder(path) else None
