"""The rule base (a classifier list and its provenance) and its versioned YAML form.

:mod:`csql_sim.core.files.rulebase` reads and writes either form by suffix (``*.npz``: the
compact form, :mod:`csql_sim.core.files.rulebase_npz`, which checks its strings with
:func:`check_strings` from here).

Format (``version: 2``)::

    format: csql-sim rule base
    version: 2
    blocks: 3
    meta: {method: cs-ql, trials: 2500, seed: 0}
    count: 918
    classifiers:
    - {kind: R, condition: 'S#1#####b#####0#', action: A10000001000ab00}
    - {kind: Q, condition: S0111000ttt0000C, action: A70000001000at00,
       strength: 0.9992, q: 0.857, age: 3.27, error: 0.0006}

A rule base whose ``meta`` records ``form: goal`` (:mod:`csql_sim.core.state.goal_message`) holds
Q-classifiers whose conditions are goal-form patterns (with ``#``); files without ``form``
(every earlier one) are in the paper's index form.

R-classifiers carry only kind, condition and action; Q-classifiers also strength, q
(Q-value), age and error (|epsilon|, prediction error). ``count`` is the number of
classifiers: a file cut anywhere, even at a line boundary, is refused. Version 1 files
(without ``count``) are refused too, since their truncation cannot be detected.

Reading is guarded (:mod:`csql_sim.infra.files`): regular files only, at most
:data:`MAX_FILE_BYTES`, no YAML aliases, bounded nesting. Every condition and action is
checked against the stated number of blocks (Q-classifiers: complete messages;
R-classifiers: :func:`csql_sim.core.classifiers.r_classifier.validate_r_classifier`), only printable
ASCII; every number must be a finite float64; ``meta`` must be plain JSON data
(:func:`check_meta`: no dates, ``!!binary``, ``!!set``, non-text keys, NaN or infinity).
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Iterable
from dataclasses import dataclass, field

import yaml

from csql_sim.core.classifiers.classifier_list import Classifier
from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import parse_r_classifier, r_classifier_problem
from csql_sim.core.state.goal_message import GoalForm, form_of, pattern_problem
from csql_sim.core.state.message import MessageError, layout, parse_action_message, parse_state_message
from csql_sim.core.state.world import MAX_BLOCKS, MIN_BLOCKS
from csql_sim.infra import formats
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import MAX_YAML_DEPTH, InputFileError, load_yaml, read_text_file

FORMAT = formats.RULE_BASE
VERSION = 2
MAX_FILE_BYTES = 16 * 1024 * 1024
_DUMPER = getattr(yaml, "CSafeDumper", yaml.SafeDumper)
"""libyaml's emitter where PyYAML has it (about four times faster, the same text as the pure-Python one)."""
"""Largest rule file read (an n=4 base is about 4.5 MB)."""
Q_FIELDS = ("strength", "q", "age", "error")


class RuleBaseError(CsqlError):
    """A missing, truncated, corrupt or foreign rule-base file."""


@dataclass
class RuleBase:
    """A classifier list read from or written to disk.

    Attributes:
        blocks: number of blocks n the messages are laid out for.
        classifiers: R- and Q-classifiers in list order.
        meta: free-form provenance (method, trials, seed, ...).

    """

    blocks: int
    classifiers: list[Classifier]
    meta: dict = field(default_factory=dict)


def dumps(rulebase: RuleBase) -> str:
    """The YAML text of a rule base."""
    rows = []
    for c in rulebase.classifiers:
        row: dict = {"kind": c.kind, "condition": c.condition, "action": c.action}
        if isinstance(c, QClassifier):
            row.update(strength=round(c.strength, 6), q=float(c.q), age=round(c.age, 6), error=round(c.error, 6))
        rows.append(row)
    doc = {
        "format": FORMAT,
        "version": VERSION,
        "blocks": rulebase.blocks,
        "meta": dict(rulebase.meta),
        "count": len(rows),
        "classifiers": rows,
    }
    return yaml.dump(doc, Dumper=_DUMPER, sort_keys=False, default_flow_style=None, width=200)


def load_file(path: str | os.PathLike, blocks: int | None = None, progress: bool = False) -> RuleBase:
    """Read a YAML rule file; see :func:`csql_sim.core.files.rulebase.load` (which also reads npz)."""
    try:
        text = read_text_file(path, MAX_FILE_BYTES, "rule file")
    except InputFileError as exc:
        raise RuleBaseError(str(exc)) from None
    return loads(text, source=os.fspath(path), blocks=blocks, progress=progress)


CHUNK_ROWS = 2000  # classifiers parsed per YAML call (one progress-bar step)


def _yaml(text: str, source: str, first_line: int = 0) -> object:
    """:func:`csql_sim.infra.files.load_yaml` of a part of a file that starts at ``first_line`` (0-based)."""
    try:
        return load_yaml(text, source)
    except InputFileError as exc:
        message = re.sub(r" at line (\d+)", lambda m: f" at line {int(m.group(1)) + first_line}", str(exc))
        raise RuleBaseError(message) from None
    except (ValueError, OverflowError) as exc:  # a value PyYAML cannot build: an integer of 5,000 digits, a bad date
        raise RuleBaseError(f"{source}: a YAML value cannot be read ({exc.__class__.__name__})") from None


def _split_header(text: str) -> tuple[str, list[str], int] | None:
    """The header text, the classifier list's lines and its first line number; None if not block style."""
    lines = text.splitlines()
    for k, line in enumerate(lines):
        if line.rstrip() == "classifiers:":
            return "\n".join(lines[:k]), lines[k + 1:], k + 1
    return None


def _header(doc: object, source: str, blocks: int | None) -> int:
    """Check the format, version and number of blocks of a parsed header; returns n."""
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise RuleBaseError(f"{source}: not a csql-sim rule base (missing 'format: {FORMAT}')")
    if doc.get("version") == 1:
        raise RuleBaseError(f"{source}: version 1 rule files record no classifier count, so a cut file cannot be "
                            f"detected; write it again with 'csql-sim train' (version {VERSION})")
    if doc.get("version") != VERSION:
        raise RuleBaseError(f"{source}: unsupported rule-base version {doc.get('version')!r} (expected {VERSION})")
    n = doc.get("blocks")
    if isinstance(n, bool) or not isinstance(n, int) or not MIN_BLOCKS <= n <= MAX_BLOCKS:
        raise RuleBaseError(f"{source}: 'blocks' must be {MIN_BLOCKS}..{MAX_BLOCKS}, got {n!r}")
    if blocks is not None and n != blocks:
        raise RuleBaseError(f"rule file {source!r} is for {n} blocks, not {blocks}")
    return n


def _rows(lines: list[str], first_line: int, source: str, progress: bool) -> list:
    """Parse a block-style YAML list in chunks of items (a progress-bar step each)."""
    from tqdm import tqdm

    starts = [k for k, line in enumerate(lines) if line.startswith("- ")] + [len(lines)]
    rows: list = []
    with tqdm(total=len(starts) - 1, desc="loading rules", unit="rule", disable=not progress, leave=False,
              delay=1.0) as bar:
        for a in range(0, len(starts) - 1, CHUNK_ROWS):
            b = min(a + CHUNK_ROWS, len(starts) - 1)
            chunk = _yaml("\n".join(lines[starts[a]:starts[b]]), source, first_line + starts[a])
            if chunk is not None and not isinstance(chunk, list):
                raise RuleBaseError(f"{source}: 'classifiers' must be a list")
            rows.extend(chunk or [])
            bar.update(b - a)
    return rows


def loads(text: str, source: str = "<string>", blocks: int | None = None, progress: bool = False) -> RuleBase:
    """Parse rule-base YAML text (see the module docstring and :func:`load`).

    The header (everything before ``classifiers:``) is parsed and checked first, so a
    file for another number of blocks is refused before its classifiers are read.
    """
    split = _split_header(text)
    if split is None:
        doc = _yaml(text, source)
        n = _header(doc, source, blocks)
        rows = doc.get("classifiers")
    else:
        head, lines, first_line = split
        doc = _yaml(head, source)
        n = _header(doc, source, blocks)
        rows = _rows(lines, first_line, source, progress)
    if not isinstance(rows, list):
        raise RuleBaseError(f"{source}: 'classifiers' must be a list")
    count = doc.get("count")
    if isinstance(count, bool) or not isinstance(count, int):
        raise RuleBaseError(f"{source}: 'count' (the number of classifiers) must be an integer, got {count!r}")
    if count != len(rows):
        raise RuleBaseError(f"{source}: holds {len(rows)} classifiers but its header says {count} (cut or edited?)")
    meta = check_meta(doc.get("meta") or {}, source)
    return RuleBase(blocks=n, classifiers=list(_classifiers(rows, n, source, _form(meta, n, source))), meta=meta)


def _form(meta: dict, n: int, source: str) -> GoalForm | None:
    """The goal form ``meta`` records (None: the index form, as in every earlier file)."""
    try:
        return form_of(meta, n, source)
    except CsqlError as exc:
        raise RuleBaseError(str(exc)) from None


def header_meta(text: str, source: str) -> dict:
    """The ``meta`` of a YAML rule file's header (before ``classifiers:``) alone; ``{}`` when it cannot be read."""
    split = _split_header(text)
    try:
        doc = load_yaml(split[0], source) if split is not None else None
    except (CsqlError, ValueError, OverflowError):
        return {}
    meta = doc.get("meta") if isinstance(doc, dict) else None
    return meta if isinstance(meta, dict) else {}


JSON_DATA = "text, a finite number, true/false, null, a list or a mapping with text keys"


def check_meta(meta: object, source: str) -> dict:
    """``meta`` if it is a mapping of plain JSON data (:data:`JSON_DATA`); else a RuleBaseError naming the key.

    Both codecs call it when reading, so ``show --json`` can print any meta it loaded and
    ``prune`` copies nothing it could not write: a YAML date, ``!!binary``, ``!!set``, a
    non-text key, NaN or infinity is refused.
    """
    if not isinstance(meta, dict):
        raise RuleBaseError(f"{source}: 'meta' must be a mapping")
    problem = _json_problem(meta, "meta", 0)
    if problem:
        raise RuleBaseError(f"{source}: {problem}")
    return meta


def _json_problem(value: object, path: str, depth: int) -> str | None:
    """Why ``value`` (at ``path`` inside meta) is not plain JSON data; None if it is."""
    if depth > MAX_YAML_DEPTH:
        return f"{path} is nested deeper than {MAX_YAML_DEPTH} levels"
    if isinstance(value, float) and not math.isfinite(value):
        return f"{path} must be finite, got {value!r}"
    if value is None or type(value) in (str, int, float, bool):
        return None
    if isinstance(value, list):
        items = ((f"{path}[{k}]", item) for k, item in enumerate(value))
    elif isinstance(value, dict):
        key = next((k for k in value if type(k) is not str), None)
        if key is not None:
            return f"{path} has the key {key!r}, not text"
        items = ((f"{path}.{k}", item) for k, item in value.items())
    else:
        return f"{path} is a {type(value).__name__}, not JSON data ({JSON_DATA})"
    return next((p for where, item in items if (p := _json_problem(item, where, depth + 1))), None)


def check_strings(kind: str, cond: str, act: str, n: int, seen: dict[str, bool],
                  form: GoalForm | None = None) -> str | None:
    """Why a classifier's condition or action does not fit n blocks (None if they fit).

    In a goal-form file (``form``) a Q-classifier's condition is a goal-form pattern
    (:func:`csql_sim.core.state.goal_message.pattern_problem`), with ``#``.
    """
    for name, value in (("condition", cond), ("action", act)):
        if not (value.isascii() and value.isprintable()):
            pos = next(p for p, ch in enumerate(value) if not (ch.isascii() and ch.isprintable()))
            return f"{name} {value!r}: position {pos} is {ascii(value[pos])}, not a message character"
    try:
        if kind == "Q" and form is not None:
            parse_action_message(act, n)
            return pattern_problem(cond, form)
        if kind == "Q":
            if cond not in seen:
                parse_state_message(cond, n)
                seen[cond] = True
            if act not in seen:
                parse_action_message(act, n)
                seen[act] = True
            return None
    except MessageError as exc:
        return f"not a {n}-block message ({exc})"
    return r_classifier_problem(cond, act, n, owner="file")


def _classifiers(rows: list, n: int, source: str, form: GoalForm | None = None) -> Iterable[Classifier]:
    width = layout(n).length
    seen: dict[str, bool] = {}
    for k, row in enumerate(rows, start=1):
        where = f"{source}: classifier {k}"
        if not isinstance(row, dict):
            raise RuleBaseError(f"{where}: expected a mapping")
        kind = row.get("kind")
        if kind not in ("R", "Q"):
            raise RuleBaseError(f"{where}: kind must be R or Q, got {kind!r}")
        cond, act = row.get("condition"), row.get("action")
        cond_width = form.length if form is not None and kind == "Q" else width
        for name, value, size in (("condition", cond, cond_width), ("action", act, width)):
            if not isinstance(value, str) or len(value) != size:
                raise RuleBaseError(f"{where}: {name} must be a {size}-character string, got {value!r}")
        problem = check_strings(kind, cond, act, n, seen, form)
        if problem:
            raise RuleBaseError(f"{where}: {problem}")
        if kind == "R":
            try:
                yield parse_r_classifier(cond, act)
            except CsqlError as exc:
                raise RuleBaseError(f"{where}: {exc}") from None
            continue
        c = QClassifier(cond, act)
        for name in Q_FIELDS:
            setattr(c, name, _number(row.get(name), name, where))
        yield c


def _number(value: object, name: str, where: str) -> float:
    """A finite float64 (age and error also non-negative); an integer too large for a float is refused."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise RuleBaseError(f"{where}: {name} must be a number, got {value!r}")
    try:
        number = float(value)
    except OverflowError:
        raise RuleBaseError(f"{where}: {name} must be a finite float64, got an integer of "
                            f"{len(str(abs(value)))} digits") from None
    if not math.isfinite(number):
        raise RuleBaseError(f"{where}: {name} must be finite, got {value!r}")
    if name in ("age", "error") and number < 0:
        raise RuleBaseError(f"{where}: {name} must be >= 0, got {value!r}")
    return number
