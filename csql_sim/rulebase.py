"""Save and load a classifier list as versioned YAML, atomically.

Format (``version: 1``)::

    format: csql-sim rule base
    version: 1
    blocks: 3
    meta: {method: cs-ql, trials: 2500, seed: 0}
    classifiers:
    - {kind: R, condition: 'S#1#####b#####0#', action: A10000001000ab00}
    - {kind: Q, condition: S0111000ttt0000C, action: A70000001000at00,
       strength: 0.9992, q: 0.857, age: 3.27, error: 0.0006}

R-classifiers carry only kind, condition and action; Q-classifiers also strength, q
(Q-value), age and error (|epsilon|, prediction error).
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from csql_sim.classifier_list import Classifier
from csql_sim.errors import CsqlError
from csql_sim.files import write_atomic
from csql_sim.message import layout
from csql_sim.q_classifier import QClassifier
from csql_sim.r_classifier import parse_r_classifier
from csql_sim.world import MAX_BLOCKS, MIN_BLOCKS

FORMAT = "csql-sim rule base"
VERSION = 1
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
        "classifiers": rows,
    }
    return yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=200)


def save(path: str | os.PathLike, rulebase: RuleBase) -> Path:
    """Write ``rulebase`` to ``path`` atomically (temporary file, then rename)."""
    return write_atomic(path, dumps(rulebase))


def load(path: str | os.PathLike) -> RuleBase:
    """Read a rule base; any problem is a one-line RuleBaseError naming the file."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise RuleBaseError(f"{p}: no such rule file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise RuleBaseError(f"{p}: cannot read rule file ({exc.__class__.__name__})") from None
    return loads(text, source=str(p))


def loads(text: str, source: str = "<string>") -> RuleBase:
    """Parse rule-base YAML text (see the module docstring)."""
    try:
        doc = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark is not None else ""
        raise RuleBaseError(f"{source}: not valid YAML{where} (truncated or corrupt?)") from None
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise RuleBaseError(f"{source}: not a csql-sim rule base (missing 'format: {FORMAT}')")
    if doc.get("version") != VERSION:
        raise RuleBaseError(f"{source}: unsupported rule-base version {doc.get('version')!r} (expected {VERSION})")
    n = doc.get("blocks")
    if not isinstance(n, int) or not MIN_BLOCKS <= n <= MAX_BLOCKS:
        raise RuleBaseError(f"{source}: 'blocks' must be {MIN_BLOCKS}..{MAX_BLOCKS}, got {n!r}")
    rows = doc.get("classifiers")
    if not isinstance(rows, list):
        raise RuleBaseError(f"{source}: 'classifiers' must be a list")
    meta = doc.get("meta") or {}
    if not isinstance(meta, dict):
        raise RuleBaseError(f"{source}: 'meta' must be a mapping")
    width = layout(n).length
    return RuleBase(blocks=n, classifiers=list(_classifiers(rows, width, source)), meta=meta)


def _classifiers(rows: list, width: int, source: str) -> Iterable[Classifier]:
    for k, row in enumerate(rows, start=1):
        where = f"{source}: classifier {k}"
        if not isinstance(row, dict):
            raise RuleBaseError(f"{where}: expected a mapping")
        kind = row.get("kind")
        if kind not in ("R", "Q"):
            raise RuleBaseError(f"{where}: kind must be R or Q, got {kind!r}")
        cond, act = row.get("condition"), row.get("action")
        for name, value in (("condition", cond), ("action", act)):
            if not isinstance(value, str) or len(value) != width:
                raise RuleBaseError(f"{where}: {name} must be a {width}-character string, got {value!r}")
        if kind == "R":
            try:
                yield parse_r_classifier(cond, act)
            except CsqlError as exc:
                raise RuleBaseError(f"{where}: {exc}") from None
            continue
        c = QClassifier(cond, act)
        for name in Q_FIELDS:
            value = row.get(name)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise RuleBaseError(f"{where}: {name} must be a number, got {value!r}")
            setattr(c, name, float(value))
        yield c
