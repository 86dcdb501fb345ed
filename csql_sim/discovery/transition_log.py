"""The transition log of a discovery run: JSON lines, a header line with the format version.

::

    {"format": "csql-sim transitions", "version": 1, "blocks": 3}
    {"before": "S0111000ttt0000C", "action": "A70000001000at00", "after": "...", "ok": true, "reason": ""}

Written atomically; read back for induction or for a peer learner (benchmarks/discovery_acs2.py).
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable
from pathlib import Path

from csql_sim.core.state.world import MAX_BLOCKS, MIN_BLOCKS
from csql_sim.discovery.induction import Experience
from csql_sim.infra import formats
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import InputFileError, load_json, read_text_file, write_atomic

MAX_FILE_BYTES = 64 * 1024 * 1024  # about 400,000 transitions
FORMAT = formats.TRANSITIONS
VERSION = 1


class TransitionLogError(CsqlError):
    """A missing, truncated or foreign transition log."""


def dumps(transitions: Iterable[Experience], n: int) -> str:
    """The log's text."""
    lines = [json.dumps({"format": FORMAT, "version": VERSION, "blocks": n})]
    for t in transitions:
        lines.append(json.dumps({"before": t.before, "action": t.action, "after": t.after, "ok": t.ok,
                                 "reason": t.reason, "refused": t.is_refusal}))
    return "\n".join(lines) + "\n"


def save(path: str | os.PathLike, transitions: Iterable[Experience], n: int) -> Path:
    """Write the log atomically."""
    return write_atomic(path, dumps(transitions, n))


def load(path: str | os.PathLike) -> tuple[int, list[Experience]]:
    """Read a log: (number of blocks, transitions).

    Raises:
        TransitionLogError: naming the file and what is wrong with it.
    """
    try:
        text = read_text_file(path, MAX_FILE_BYTES, "transition log")
    except InputFileError as exc:
        raise TransitionLogError(str(exc)) from None
    rows = text.splitlines()
    try:  # each line through the guarded reader: bounded nesting and digits, one line naming the file
        head = load_json(rows[0], f"{path} line 1") if rows else {}
        if not isinstance(head, dict) or head.get("format") != FORMAT or head.get("version") != VERSION:
            raise TransitionLogError(f"{path} is not a version-{VERSION} {FORMAT!r} file")
        n = head.get("blocks")
        if type(n) is not int or not MIN_BLOCKS <= n <= MAX_BLOCKS:
            raise TransitionLogError(f"{path}: 'blocks' must be {MIN_BLOCKS}..{MAX_BLOCKS}, got {str(n)[:20]!r}")
        out = [Experience(r["before"], r["action"], r["after"], bool(r["ok"]), r.get("reason", ""), r.get("refused"))
               for r in (load_json(row, f"{path} line {k}") for k, row in enumerate(rows[1:], 2))]
    except InputFileError as exc:
        raise TransitionLogError(str(exc)) from None
    except (KeyError, TypeError, AttributeError) as exc:
        raise TransitionLogError(f"{path}: corrupt transition log ({exc.__class__.__name__}: {str(exc)[:80]})") \
            from None
    return n, out
