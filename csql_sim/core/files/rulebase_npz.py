"""Compact rule bases: a classifier list as numpy arrays in a ``.npz`` file.

Format (``version: 1``), one array per field, every classifier in list order:

* ``header``: a 0-d unicode array holding JSON ``{"format": "csql-sim rule base (npz)",
  "version": 1, "blocks": n, "count": N, "meta": {...}}``;
* ``kind`` (``S1``, ``R`` or ``Q``), ``condition`` and ``action`` (ASCII bytes, one
  message-length string each);
* ``q``, ``strength``, ``age``, ``error`` (float64; 0 for R-classifiers, which carry
  none of them in the YAML form).

The file is a zip archive written with ``numpy.savez_compressed`` (CRC-checked members)
and read with ``allow_pickle=False``. A file cut anywhere is refused: the zip's central
directory is at its end, every member is CRC-checked, and ``count`` must equal the
length of every array. In a goal-form file (``meta.form: goal``,
:mod:`csql_sim.core.state.goal_message`) the conditions are goal-form patterns (``#`` allowed)
of that form's length, and only Q-classifiers are held. The same classifier list written as YAML and as npz reads back
to the same classifiers (the npz keeps the full float64 values). Reading checks what the
YAML reader checks (messages, R-classifier patterns, ``meta`` as JSON data), every byte
of a message is printable ASCII, and the header is at most :data:`MAX_HEADER_CHARS`
characters nested at most 32 levels deep.
"""

from __future__ import annotations

import io
import json
import os
import zipfile
from pathlib import Path

import numpy as np

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import parse_r_classifier
from csql_sim.core.files.rulebase_yaml import RuleBase, check_meta, check_strings
from csql_sim.core.state.goal_message import GoalForm, form_of
from csql_sim.core.state.message import layout
from csql_sim.core.state.message_index import known_action, known_state
from csql_sim.core.state.world import MAX_BLOCKS, MIN_BLOCKS
from csql_sim.infra import formats
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import MAX_YAML_DEPTH, InputFileError, load_json, read_bytes_file, write_atomic

FORMAT = formats.RULE_BASE_NPZ
VERSION = 1
FLOATS = ("q", "strength", "age", "error")
MAX_FILE_BYTES = 256 * 1024 * 1024
"""Largest npz rule file read (a 5-block base is about 35 MB)."""
MAX_EXPANDED_BYTES = 2 * 1024 * 1024 * 1024
"""Largest total of its arrays once decompressed (5 blocks: about 125 MB)."""
ARRAYS = ("header", "kind", "condition", "action", *FLOATS)
MAX_HEADER_CHARS = 1024 * 1024
"""Longest JSON header read (a trained file's is about 1 kB); it may nest at most
:data:`~csql_sim.infra.files.MAX_YAML_DEPTH` levels, as YAML rule files."""


def to_bytes(rulebase: RuleBase) -> bytes:
    """The npz bytes of a :class:`~csql_sim.core.files.rulebase.RuleBase`."""
    return arrays_to_bytes(rulebase.blocks, rulebase.meta, to_arrays(rulebase))


def to_arrays(rulebase: RuleBase) -> dict[str, np.ndarray]:
    """A rule base's classifiers as the npz form's arrays (every classifier, list order)."""
    cs = rulebase.classifiers
    width = layout(rulebase.blocks).length
    cond_width = _condition_width(rulebase.blocks, rulebase.meta, "rule base", CsqlError)
    if cond_width != width and any(not isinstance(c, QClassifier) for c in cs):
        raise CsqlError("a goal-form rule base in npz holds Q-classifiers only (its R-classifiers are "
                        "index-form messages of another length); write it as YAML")
    arrays = {
        "kind": np.array([c.kind for c in cs], dtype="S1"),
        "condition": np.array([c.condition for c in cs], dtype=f"S{cond_width}"),
        "action": np.array([c.action for c in cs], dtype=f"S{width}"),
    }
    for name in FLOATS:
        arrays[name] = np.array([getattr(c, name) if isinstance(c, QClassifier) else 0.0 for c in cs],
                                dtype=np.float64)
    return arrays


def arrays_to_bytes(blocks: int, meta: dict, arrays: dict[str, np.ndarray]) -> bytes:
    """The npz bytes of a classifier list given as arrays (``kind``, ``condition``, ...)."""
    count = len(arrays["kind"])
    header = {"format": FORMAT, "version": VERSION, "blocks": blocks, "count": count, "meta": dict(meta)}
    out = io.BytesIO()
    np.savez_compressed(out, header=np.array(json.dumps(header)), **{k: arrays[k] for k in ARRAYS[1:]})
    return out.getvalue()


def save(path: str | os.PathLike, rulebase: RuleBase) -> Path:
    """Write ``rulebase`` as npz atomically."""
    return write_atomic(path, to_bytes(rulebase))


def read_arrays(path: str | os.PathLike, source: str, error: type[Exception]) -> tuple[dict, dict[str, np.ndarray]]:
    """The checked header and arrays of an npz rule file; any problem raises ``error``."""
    try:
        data = read_bytes_file(path, MAX_FILE_BYTES, "rule file")
    except InputFileError as exc:
        raise error(str(exc)) from None
    return arrays_from_bytes(data, source, error)


def arrays_from_bytes(data: bytes, source: str, error: type[Exception]) -> tuple[dict, dict[str, np.ndarray]]:
    """:func:`read_arrays` of a file's bytes, read already (``source`` names it in messages)."""
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as z:
            expanded = sum(info.file_size for info in z.infolist())
        if expanded > MAX_EXPANDED_BYTES:
            raise error(f"{source}: expands to {expanded:,} bytes, above the {MAX_EXPANDED_BYTES:,}-byte limit")
        with np.load(io.BytesIO(data), allow_pickle=False) as z:
            missing = [name for name in ARRAYS if name not in z.files]
            arrays = {} if missing else {name: z[name] for name in ARRAYS}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError) as exc:
        raise error(f"{source}: unreadable npz rule base (truncated or corrupt? {exc.__class__.__name__})") from None
    if missing:
        raise error(f"{source}: not a csql-sim npz rule base (no {missing[0]!r} array)")
    header = _header(arrays.pop("header"), source, error)
    count, width = header["count"], layout(header["blocks"]).length
    widths = {"condition": _condition_width(header["blocks"], header.get("meta", {}), source, error),
              "action": width}
    for name, array in arrays.items():
        if array.ndim != 1 or array.shape[0] != count:
            raise error(f"{source}: array {name!r} holds {array.shape} entries, the header says {count} (truncated?)")
    for name, size in widths.items():
        if arrays[name].dtype != np.dtype(f"S{size}"):
            raise error(f"{source}: {name}s must be {size}-character strings, got {arrays[name].dtype}")
        _check_bytes(arrays[name], name, size, source, error)
    if arrays["kind"].dtype != np.dtype("S1") or not np.isin(arrays["kind"], (b"R", b"Q")).all():
        raise error(f"{source}: every kind must be R or Q")
    for name in FLOATS:
        values = arrays[name]
        if values.dtype != np.float64:
            raise error(f"{source}: {name} must be float64, got {values.dtype}")
        if not np.isfinite(values).all():
            raise error(f"{source}: classifier {int(np.argmin(np.isfinite(values))) + 1}: {name} must be finite")
        if name in ("age", "error") and (values < 0).any():
            raise error(f"{source}: classifier {int(np.argmax(values < 0)) + 1}: {name} must be >= 0")
    _check_messages(header["blocks"], arrays, source, error, form_of(header.get("meta", {}), header["blocks"]))
    return header, arrays


def _condition_width(n: int, meta: dict, source: str, error: type[Exception]) -> int:
    """Conditions are index-form messages, or goal-form patterns when ``meta`` records the goal form."""
    try:
        form = form_of(meta, n, source)
    except CsqlError as exc:
        raise error(str(exc)) from None
    return layout(n).length if form is None else form.length


def header_meta(data: bytes) -> dict:
    """The ``meta`` of an npz rule file's header array alone, from the file's bytes; ``{}`` when it cannot be read."""
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as archive, archive.open("header.npy") as member:
            raw = np.lib.format.read_array(member, allow_pickle=False)
        if raw.ndim != 0 or raw.dtype.kind != "U" or raw.dtype.itemsize // 4 > MAX_HEADER_CHARS:
            return {}
        meta = load_json(str(raw[()]), "npz header", max_depth=MAX_YAML_DEPTH).get("meta")
    except (CsqlError, OSError, KeyError, ValueError, AttributeError, zipfile.BadZipFile, RuntimeError):
        return {}
    return meta if isinstance(meta, dict) else {}


def _check_messages(n: int, arrays: dict[str, np.ndarray], source: str, error: type[Exception],
                    form: GoalForm | None = None) -> None:
    """Every condition and action fits n blocks, as the YAML loader checks (per distinct string).

    Q-classifiers' conditions are state messages and their actions action messages; the
    common case (a known state body and goal code, a known action message) is checked with
    numpy, anything else by the YAML loader's own checks.
    """
    is_q = arrays["kind"] == b"Q"
    odd = ~is_q
    if form is None:
        odd[is_q] = ~(known_state(n, arrays["condition"][is_q]) & known_action(n, arrays["action"][is_q]))
    else:
        odd[is_q] = True  # goal-form patterns: each checked (a compacted base holds few)
    seen: dict[str, bool] = {}
    for k in np.flatnonzero(odd).tolist():
        kind, cond, act = (arrays[x][k].decode("ascii", "replace") for x in ("kind", "condition", "action"))
        problem = check_strings(kind, cond, act, n, seen, form)
        if problem:
            raise error(f"{source}: classifier {k + 1}: {problem}")


def _check_bytes(strings: np.ndarray, name: str, width: int, source: str, error: type[Exception]) -> None:
    """Every byte of every message is a printable ASCII character (no NUL padding: all are ``width`` long)."""
    codes = np.ascontiguousarray(strings).view(np.uint8).reshape(len(strings), width)
    bad = (codes < 0x21) | (codes > 0x7E)
    if bad.any():
        k, pos = (int(i) for i in np.argwhere(bad)[0])
        raise error(f"{source}: classifier {k + 1}: {name} holds the byte 0x{codes[k, pos]:02x} at position {pos}, "
                    f"not a message character")


def _header(raw: np.ndarray, source: str, error: type[Exception]) -> dict:
    if raw.ndim != 0 or raw.dtype.kind != "U":
        raise error(f"{source}: the npz header is not JSON text")
    if raw.dtype.itemsize // 4 > MAX_HEADER_CHARS:
        raise error(f"{source}: the npz header is {raw.dtype.itemsize // 4:,} characters, above the "
                    f"{MAX_HEADER_CHARS:,}-character limit")
    try:
        header = load_json(str(raw[()]), f"{source}: the npz header", max_depth=MAX_YAML_DEPTH)
    except InputFileError as exc:
        raise error(str(exc)) from None
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        raise error(f"{source}: not a csql-sim npz rule base (missing format {FORMAT!r})")
    if header.get("version") != VERSION:
        raise error(f"{source}: unsupported npz rule-base version {header.get('version')!r} (expected {VERSION})")
    n, count = header.get("blocks"), header.get("count")
    if type(n) is not int or not MIN_BLOCKS <= n <= MAX_BLOCKS:
        raise error(f"{source}: 'blocks' must be {MIN_BLOCKS}..{MAX_BLOCKS}, got {n!r}")
    if type(count) is not int or count < 0:
        raise error(f"{source}: 'count' must be a non-negative integer, got {count!r}")
    try:
        check_meta(header.get("meta", {}), source)
    except CsqlError as exc:
        raise error(str(exc)) from None
    return header


def load(path: str | os.PathLike, error: type[Exception]) -> RuleBase:
    """Read an npz rule file into a :class:`~csql_sim.core.files.rulebase.RuleBase`."""
    try:
        data = read_bytes_file(path, MAX_FILE_BYTES, "rule file")
    except InputFileError as exc:
        raise error(str(exc)) from None
    return loads(data, os.fspath(path), error)


def loads(data: bytes, source: str, error: type[Exception]) -> RuleBase:
    """:func:`load` of a file's bytes, read already (``source`` names it in messages)."""
    header, a = arrays_from_bytes(data, source, error)
    kinds = a["kind"].tolist()
    conds = a["condition"].astype(f"U{a['condition'].dtype.itemsize}").tolist()
    acts = a["action"].astype(f"U{a['action'].dtype.itemsize}").tolist()
    floats = [a[name].tolist() for name in FLOATS]
    out: list = []
    for k, (kind, cond, act, q, strength, age, err) in enumerate(zip(kinds, conds, acts, *floats, strict=True)):
        if kind == b"Q":
            out.append(QClassifier(cond, act, q, strength, age, err))
            continue
        try:
            out.append(parse_r_classifier(cond, act))
        except CsqlError as exc:
            raise error(f"{source}: classifier {k + 1}: {exc}") from None
    return RuleBase(blocks=header["blocks"], classifiers=out, meta=header.get("meta", {}))
