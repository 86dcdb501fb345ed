"""Writing a command's result: JSON (``--json [FILE]``) or text, the same way everywhere."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any

from csql_sim.infra.files import atomic_output, check_output_file, write_or_keep
from csql_sim.infra.provenance import provenance

NOT_PARAMETERS = ("func", "json", "quiet")  # how a command reports, not what it computes


def json_text(doc: Any) -> str:
    """The JSON text of a document (indented, one trailing newline)."""
    return json.dumps(doc, indent=1) + "\n"


def emit(args: argparse.Namespace, doc: Any,
         text: Callable[[], Iterable[str] | str] | str | None = None) -> Path | None:
    """Print the result of a command.

    With ``--json`` (``args.json`` not None) the document is written as JSON instead of
    text: to stdout for ``-``, otherwise atomically to the file (its name is reported on
    stderr). Without it, ``text`` (a string, or a function giving a string or lines) is
    printed; it is only computed when needed.

    A JSON object without a ``"provenance"`` entry gets one: the package version and the
    command's parameters (:func:`command_parameters`).

    Returns:
        The JSON file written, if any.
    """
    target = getattr(args, "json", None)
    if target is not None:
        if isinstance(doc, dict) and "provenance" not in doc:
            doc = {**doc, "provenance": provenance(**command_parameters(args))}
        if target == "-":
            sys.stdout.write(json_text(doc))
            return None
        path = write_or_keep([(target, json_text(doc))])[0]
        print(f"wrote {path}", file=sys.stderr)
        return path
    if text is None:
        return None
    lines = text() if callable(text) else text
    for line in [lines] if isinstance(lines, str) else lines:
        print(line)
    return None


def wants_json(args: argparse.Namespace) -> bool:
    """Whether ``--json`` was given."""
    return getattr(args, "json", None) is not None


def command_parameters(args: argparse.Namespace) -> dict[str, Any]:
    """The subcommand and every parameter it ran with (defaults included)."""
    return {k: v for k, v in vars(args).items() if k not in NOT_PARAMETERS}


def check_json_output(args: argparse.Namespace) -> None:
    """Before any work: a ``--json FILE`` must be writable (one-line OutputError otherwise)."""
    target = getattr(args, "json", None)
    if target not in (None, "-"):
        check_output_file(target, "JSON report")


@contextmanager
def json_stream(args: argparse.Namespace) -> Iterator[IO[str] | None]:
    """A text stream for JSON written piece by piece: stdout, or FILE renamed into place at the end.

    Yields None without ``--json``.
    """
    target = getattr(args, "json", None)
    if target is None:
        yield None
    elif target == "-":
        yield sys.stdout
    else:
        with atomic_output(target) as tmp, open(tmp, "w", encoding="utf-8") as fh:
            yield fh
        print(f"wrote {target}", file=sys.stderr)
