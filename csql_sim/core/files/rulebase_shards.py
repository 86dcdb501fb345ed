"""Sharded rule bases: one directory, a manifest and one file of arrays per shard of goals.

Goal-sharded training (:mod:`csql_sim.learners.training.shards`) writes, in a directory ``D``:

* ``D/manifest.json``: format ``csql-sim-shards`` version 1; what determines the content
  (method, blocks, seed, trials, shards, the parameters, the R-classifiers, provenance);
  ``complete`` (false while shards are missing); one entry per shard written (its file,
  SHA-256, goal range, Q-classifier count, clock). Never how it was computed: workers,
  backend and times go to ``D/run-report.json``, so two runs with other workers or
  another backend write byte-identical manifests and shards.
* ``D/shard-KKKKK.bin``: shard ``K``: a header (magic, then one JSON line: format,
  version, shard, clock and each array's dtype, length and byte offset), then the arrays,
  memory-mapped on read. A shard holds its goals' Q-classifiers, goal-major and by
  state: ``first[goal_local * S + state]`` is the node's first slot (-1: never covered),
  its candidates (the R-classifiers' order) are the consecutive slots of ``q`` and
  ``error``; ``born`` is the clock the node was covered (age = (clock - born) / age unit);
  strength is 1 - error.

Readers open a shard only when a pair of its goals is asked for, check its SHA-256 first
(a corrupt shard is refused by name), and refuse an incomplete directory in one line.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from csql_sim.core.files.rulebase_yaml import RuleBaseError
from csql_sim.core.state.state_count import state_count
from csql_sim.infra import formats
from csql_sim.infra.files import InputFileError, load_json, read_json_file, write_atomic

FORMAT = formats.SHARDS
VERSION = 1
MANIFEST = formats.SHARD_MANIFEST
REPORT = "run-report.json"
MAGIC = formats.SHARD_MAGIC + b"\n"
ARRAYS = (("first", "<i8"), ("born", "<i8"), ("q", "<f8"), ("error", "<f8"))
ALIGN = 64
MAX_HEADER = 4096
MAX_MANIFEST_BYTES = 1 << 26
MAX_BLOCKS = 7
"""The most blocks a sharded rule base may be for (7: the estimate's; training and reading stop at 6)."""
_OWN_NAME = re.compile(r"shard-\d{5}\.bin|" + re.escape(MANIFEST) + "|" + re.escape(REPORT))


@dataclass(frozen=True)
class ShardArrays:
    """One shard's Q-classifiers (see the module docstring for the layout).

    Attributes:
        first: each node's first slot, ``[goal_local * S + state]``; -1 where never covered.
        born: the clock each node was covered (0 where never covered).
        q: Q-value per slot.
        error: |epsilon| per slot, settled to ``clock``.
        clock: the shard's clock (learning steps) when it was written.

    """

    first: np.ndarray
    born: np.ndarray
    q: np.ndarray
    error: np.ndarray
    clock: int


def shard_name(index: int) -> str:
    """The file name of shard ``index``."""
    return f"shard-{index:05d}.bin"


def shard_bytes(index: int, arrays: ShardArrays) -> bytes:
    """The content of shard ``index``'s file."""
    table, offset = {}, 0
    for name, dtype in ARRAYS:
        length = len(getattr(arrays, name))
        table[name] = [dtype, length, offset]
        offset += -(-length * np.dtype(dtype).itemsize // ALIGN) * ALIGN
    header = json.dumps({"format": FORMAT, "version": VERSION, "shard": index, "clock": arrays.clock,
                         "arrays": table}, sort_keys=True).encode("ascii") + b"\n"
    start = -(-(len(MAGIC) + len(header)) // ALIGN) * ALIGN
    body = bytearray(start + offset)
    body[: len(MAGIC) + len(header)] = MAGIC + header
    for name, dtype in ARRAYS:
        _, length, at = table[name]
        data = np.ascontiguousarray(getattr(arrays, name), dtype=dtype).tobytes()
        body[start + at: start + at + len(data)] = data
    return bytes(body)


def file_sha256(path: Path) -> str:
    """The SHA-256 of a file, read in 8 MB blocks."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 23), b""):
            h.update(block)
    return h.hexdigest()


def read_shard(path: Path, index: int, sha256: str | None, nodes: int | None = None) -> ShardArrays:
    """Shard ``index`` from ``path``, memory-mapped; its SHA-256 is checked first when given.

    Args:
        path: the shard's file.
        index: the shard's index (its header must say the same).
        sha256: the manifest's SHA-256 of the file (None: not checked).
        nodes: the number of (goal, state) nodes the shard must hold (None: not checked).

    Raises:
        RuleBaseError: naming the shard, if it is missing, corrupt or another shard's file.
    """
    where = f"shard {index} ({path})"
    try:
        if path.is_symlink() or not path.is_file():
            raise RuleBaseError(f"{where} is not a regular file")
        if sha256 is not None and file_sha256(path) != sha256:
            raise RuleBaseError(f"{where} is corrupt: its SHA-256 differs from the manifest's; train it again "
                                "(delete the file and run csql-sim train --resume)")
        with open(path, "rb") as f:
            head = f.read(MAX_HEADER)
        size = path.stat().st_size
    except OSError as exc:
        raise RuleBaseError(f"cannot read {where}: {exc.strerror or exc}") from None
    line = head[len(MAGIC):].split(b"\n", 1)[0]
    try:
        if not head.startswith(MAGIC):
            raise ValueError("no shard header")
        header = load_json(line.decode("utf-8"), "its header")
        if not isinstance(header, dict):
            raise ValueError("its header is not a JSON object")
        if header.get("format") != FORMAT or header.get("version") != VERSION or header.get("shard") != index:
            raise ValueError("another format, version or shard")
        start = -(-(len(MAGIC) + len(line) + 1) // ALIGN) * ALIGN
        out = {}
        for name, dtype in ARRAYS:
            kind, length, at = header["arrays"][name]
            if kind != dtype or not (isinstance(length, int) and isinstance(at, int)) or length < 0 or at < 0 \
                    or start + at + length * np.dtype(dtype).itemsize > size:
                raise ValueError(f"array {name} out of bounds")
            out[name] = np.memmap(path, dtype=dtype, mode="r", offset=start + at, shape=(length,)) if length \
                else np.zeros(0, dtype)
        arrays = ShardArrays(out["first"], out["born"], out["q"], out["error"], int(header["clock"]))
        _check_layout(arrays, header, nodes)
        return arrays
    except (ValueError, KeyError, TypeError) as exc:
        raise RuleBaseError(f"{where} is corrupt: {exc}") from None


def _check_layout(arrays: ShardArrays, header: dict, nodes: int | None) -> None:
    """Raise ValueError unless the header is what :func:`shard_bytes` writes for these arrays and they fit together."""
    expected = json.loads(shard_bytes(header["shard"], ShardArrays(*(np.zeros(0),) * 4, arrays.clock))
                          [len(MAGIC):].split(b"\n", 1)[0])["arrays"]
    offset = 0
    for name, dtype in ARRAYS:
        length = len(getattr(arrays, name))
        expected[name] = [dtype, length, offset]
        offset += -(-length * np.dtype(dtype).itemsize // ALIGN) * ALIGN
    if header["arrays"] != expected:
        raise ValueError("its header's layout is not the one this format writes")
    if len(arrays.first) != len(arrays.born) or len(arrays.q) != len(arrays.error):
        raise ValueError("arrays of different lengths")
    if nodes is not None and len(arrays.first) != nodes:
        raise ValueError(f"{len(arrays.first)} nodes, not {nodes}")
    if len(arrays.first) and (int(arrays.first.min()) < -1 or int(arrays.first.max()) >= max(len(arrays.q), 1)):
        raise ValueError("a node's first slot lies outside its Q-values")


def is_own_file(path: Path) -> bool:
    """Whether ``path`` is one of the files a sharded rule base's directory holds (a regular file, our name)."""
    return _OWN_NAME.fullmatch(path.name) is not None and path.is_file() and not path.is_symlink()


def check_own_files(directory: Path) -> None:
    """Refuse, before any write, a link, folder or device named as one of the directory's own files.

    The tool replaces its files there atomically and never writes through a link: a link
    named ``shard-00000.bin`` (or a folder so named) is the user's, refused in one line.

    Raises:
        RuleBaseError: naming the entry and what it is.
    """
    try:
        entries = sorted(os.scandir(directory), key=lambda e: e.name)
    except (FileNotFoundError, NotADirectoryError):
        return
    except OSError as exc:
        raise RuleBaseError(f"cannot list {directory}: {exc.strerror or exc}") from None
    for entry in entries:
        if _OWN_NAME.fullmatch(entry.name) and not entry.is_file(follow_symlinks=False):
            kind = "a symbolic link" if entry.is_symlink() else "a folder" if entry.is_dir(follow_symlinks=False) \
                else "a device, pipe or socket"
            raise RuleBaseError(f"{Path(directory) / entry.name} is {kind}, not a regular file; refusing to write "
                                "through or replace it (remove it, or give another --out)")


def is_sharded(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a directory holding a sharded rule base's manifest."""
    p = Path(path)
    return p.is_dir() and (p / MANIFEST).is_file()


def write_manifest(directory: Path, manifest: dict) -> Path:
    """Write ``manifest.json`` atomically (sorted keys: the same content, the same bytes); a link there is replaced."""
    return write_atomic(directory / MANIFEST, json.dumps(manifest, indent=1, sort_keys=True) + "\n", follow_links=False)


def read_manifest(directory: Path) -> dict:
    """The manifest of ``directory``, every field checked (:func:`check_manifest`).

    Raises:
        RuleBaseError: one line naming the file (and the field), if it is missing, not
            JSON (or nested too deep), foreign or has a field of the wrong type or value.
    """
    path = directory / MANIFEST
    try:
        manifest = read_json_file(path, MAX_MANIFEST_BYTES, "manifest")
    except InputFileError as exc:
        raise RuleBaseError(str(exc)) from None
    if not isinstance(manifest, dict) or manifest.get("format") != FORMAT:
        raise RuleBaseError(f"{path} is not a sharded rule base's manifest (format {FORMAT!r})")
    if manifest.get("version") != VERSION:
        raise RuleBaseError(f"{path} has version {_shown(manifest.get('version'))}; this csql-sim reads version "
                            f"{VERSION}")
    check_manifest(manifest, path)
    return manifest


def _shown(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _bad(path: Path, field: str, value: object, what: str) -> RuleBaseError:
    return RuleBaseError(f"{path}: field {field!r} must be {what}, got {_shown(value)}")


def _whole(value: object, low: int, high: int | None = None) -> bool:
    return type(value) is int and value >= low and (high is None or value <= high)


def check_manifest(manifest: dict, path: Path) -> None:
    """Check every field that reading or ``train --resume`` uses: types, ranges, and each shard entry.

    Raises:
        RuleBaseError: naming ``path`` and the first field that is missing or wrong.
    """
    for key, low, high in (("blocks", 2, MAX_BLOCKS), ("seed", 0, None), ("trials", 0, None)):
        if not _whole(manifest.get(key), low, high):
            raise _bad(path, key, manifest.get(key), f"an integer {low}..{high}" if high else f"an integer >= {low}")
    count = state_count(manifest["blocks"])
    if manifest.get("count") != count or type(manifest.get("count")) is not int:
        raise _bad(path, "count", manifest.get("count"), f"{count} (the states of {manifest['blocks']} blocks)")
    if not _whole(manifest.get("shards"), 1, count):
        raise _bad(path, "shards", manifest.get("shards"), f"an integer 1..{count}")
    if manifest.get("method") != "cs-ql":
        raise _bad(path, "method", manifest.get("method"), "'cs-ql'")
    if not isinstance(manifest.get("params"), dict):
        raise _bad(path, "params", manifest.get("params"), "an object")
    rules = manifest.get("r_classifiers")
    if not isinstance(rules, list) or not all(isinstance(r, list) and len(r) == 2 and all(isinstance(x, str) for x in r)
                                              for r in rules):
        raise _bad(path, "r_classifiers", rules, "a list of [condition, action] pairs")
    files = manifest.get("files")
    if not isinstance(files, list) or len(files) > manifest["shards"]:
        raise _bad(path, "files", files, f"a list of at most {manifest['shards']} shard entries")
    seen: set[int] = set()
    for k, entry in enumerate(files):
        _check_entry(path, k, entry, manifest, seen)
    if type(manifest.get("complete")) is not bool or manifest["complete"] != (len(seen) == manifest["shards"]):
        raise _bad(path, "complete", manifest.get("complete"), f"{len(seen) == manifest['shards']} "
                   f"({len(seen)} of {manifest['shards']} shards listed)")


def _check_entry(path: Path, k: int, entry: object, manifest: dict, seen: set[int]) -> None:
    """One entry of the manifest's ``files``: its shard (once each), file name, SHA-256, goals, counts."""
    field = f"files[{k}]"
    if not isinstance(entry, dict):
        raise _bad(path, field, entry, "an object")
    shard = entry.get("shard")
    if not _whole(shard, 0, manifest["shards"] - 1) or shard in seen:
        raise _bad(path, f"{field}.shard", shard, f"a shard 0..{manifest['shards'] - 1} listed once")
    seen.add(shard)
    if entry.get("file") != shard_name(shard):
        raise _bad(path, f"{field}.file", entry.get("file"), repr(shard_name(shard)))
    sha = entry.get("sha256")
    if not (isinstance(sha, str) and re.fullmatch(r"[0-9a-f]{64}", sha)):
        raise _bad(path, f"{field}.sha256", sha, "64 hexadecimal digits")
    goals = list(goal_range(manifest["count"], manifest["shards"], shard))
    if entry.get("goals") != goals:
        raise _bad(path, f"{field}.goals", entry.get("goals"), str(goals))
    for key in ("q_classifiers", "clock"):
        if not _whole(entry.get(key), 0):
            raise _bad(path, f"{field}.{key}", entry.get(key), "an integer >= 0")


def goal_range(count: int, shards: int, index: int) -> tuple[int, int]:
    """The goals ``lo .. hi - 1`` of shard ``index`` of ``shards`` over ``count`` states (contiguous, balanced)."""
    return index * count // shards, (index + 1) * count // shards


class ShardedRuleBase:
    """A sharded rule base opened for reading: shards are read (and checked) on first use.

    Args:
        directory: the rule base's directory.
        manifest: its manifest (:func:`read_manifest`).

    Raises:
        RuleBaseError: if the directory is incomplete (a run stopped early) or the
            manifest's shard list does not match its shard count.
    """

    def __init__(self, directory: Path, manifest: dict) -> None:
        self.directory, self.manifest = directory, manifest
        self.blocks, self.shards, self.count = manifest["blocks"], manifest["shards"], manifest["count"]
        if not (2 <= self.blocks <= 6 and 1 <= self.count <= 10**6 and 1 <= self.shards <= self.count
                and len(manifest["files"]) <= self.shards):
            raise RuleBaseError(f"{directory / MANIFEST}: blocks, count, shards or files out of range")
        if not manifest["complete"]:
            raise RuleBaseError(f"rule base {os.fspath(directory)!r} is incomplete ({len(manifest['files'])} of "
                                f"{self.shards} shards): continue it with csql-sim train --resume --out {directory}")
        entries = {e.get("shard"): e for e in manifest["files"] if isinstance(e, dict)}
        if sorted(k for k in entries if isinstance(k, int)) != list(range(self.shards)):
            raise RuleBaseError(f"{directory / MANIFEST}: the shard list does not match {self.shards} shards")
        self.entries = entries
        self.verified: set[int] = set()  # shards whose SHA-256 was checked in this process
        self.shard = functools.lru_cache(maxsize=8)(self._shard)

    @classmethod
    def open(cls, path: str | os.PathLike, blocks: int | None = None) -> ShardedRuleBase:
        """Open the sharded rule base at ``path`` (a directory), for ``blocks`` blocks if given."""
        directory = Path(path)
        base = cls(directory, read_manifest(directory))
        if blocks is not None and base.blocks != blocks:
            raise RuleBaseError(f"rule base {os.fspath(path)!r} is for {base.blocks} blocks, not {blocks}")
        return base

    def _shard(self, index: int) -> ShardArrays:
        entry = self.entries[index]
        name = entry.get("file")
        if name != shard_name(index):
            raise RuleBaseError(f"{self.directory / MANIFEST}: shard {index} names file {name!r}")
        lo, hi = goal_range(self.count, self.shards, index)
        sha = None if index in self.verified else entry["sha256"]  # each shard is hashed once
        arrays = read_shard(self.directory / name, index, sha, (hi - lo) * self.count)
        self.verified.add(index)
        return arrays

    def shard_of(self, goal: int) -> int:
        """The shard that holds ``goal``'s Q-classifiers."""
        k = (goal * self.shards) // self.count
        while goal_range(self.count, self.shards, k)[0] > goal:
            k -= 1
        while goal_range(self.count, self.shards, k)[1] <= goal:
            k += 1
        return k

    def column(self, goal: int) -> tuple[ShardArrays, int]:
        """The shard holding ``goal`` and the index of the goal's first node in it (its states follow)."""
        k = self.shard_of(goal)
        return self.shard(k), (goal - goal_range(self.count, self.shards, k)[0]) * self.count

    def node(self, state: int, goal: int) -> tuple[ShardArrays, int]:
        """The shard holding (state, goal) and the node's first slot there (-1: never covered)."""
        arrays, start = self.column(goal)
        return arrays, int(arrays.first[start + state])


def greedy_ranks(first: np.ndarray, q: np.ndarray, widths: np.ndarray, count: int) -> np.ndarray:
    """Per node of a shard, the rank of its greedy candidate (the first highest Q); -1 where never covered.

    Args:
        first: the shard's ``first`` array (nodes ``[goal_local * count + state]``).
        q: the shard's Q-values (nodes' slots consecutive, in node order).
        widths: the number of candidates of each state.
        count: the number of states.
    """
    rank = np.full(len(first), -1, np.int64)
    nodes = np.flatnonzero(first >= 0)
    if not len(nodes):
        return rank
    starts = np.asarray(first[nodes], np.int64)
    sizes = widths[nodes % count]
    at = np.zeros(len(nodes), np.int64)  # each node's segment in the gathered values
    at[1:] = np.cumsum(sizes)[:-1]
    local = np.arange(int(sizes.sum())) - np.repeat(at, sizes)
    values = np.asarray(q)[np.repeat(starts, sizes) + local]
    top = np.maximum.reduceat(values, at)
    candidate = np.where(values == np.repeat(top, sizes), local, np.iinfo(np.int64).max)
    rank[nodes] = np.minimum.reduceat(candidate, at)
    return rank
