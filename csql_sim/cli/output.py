"""Writing a command's result: JSON (``--json [FILE]``) or text, the same way everywhere.

Before a command runs, :func:`plan_outputs` declares and checks all its outputs (its
``--json`` file and whatever its ``declare`` function adds) in one
:class:`csql_sim.infra.outputs.Outputs`. Every JSON report carries ``"format"`` and
``"version"`` first (:func:`with_format`).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any

from csql_sim.infra.files import OutputError, atomic_output, write_or_keep
from csql_sim.infra.outputs import Outputs
from csql_sim.infra.provenance import provenance

NOT_PARAMETERS = ("func", "declare", "json", "quiet", "overwrite", "mode_options", "ignored")
"""How a command reports and reads its options, not what it computes."""
REPORT_VERSION = 1
"""The version of the JSON reports whose format :func:`with_format` names."""


def json_text(doc: Any) -> str:
    """The JSON text of a document (indented, one trailing newline)."""
    return json.dumps(doc, indent=1) + "\n"


def report_format(args: argparse.Namespace) -> str:
    """The format name of a command's JSON report: ``csql-sim <command> report``."""
    return f"csql-sim {getattr(args, 'command', None) or 'command'} report"


def with_format(doc: dict, name: str, version: int = REPORT_VERSION) -> dict:
    """``doc`` with ``"format": name`` and ``"version"`` first (a doc that names its format is kept)."""
    if "format" in doc:
        return doc
    return {"format": name, "version": version, **doc}


def emit(args: argparse.Namespace, doc: Any,
         text: Callable[[], Iterable[str] | str] | str | None = None) -> Path | None:
    """Print the result of a command.

    With ``--json`` (``args.json`` not None) the document is written as JSON instead of
    text: to stdout for ``-``, otherwise atomically to the file (its name is reported on
    stderr). Without it, ``text`` (a string, or a function giving a string or lines) is
    printed; it is only computed when needed.

    A JSON object without a ``"provenance"`` entry gets one: the package version and the
    command's parameters (:func:`command_parameters`); one without a ``"format"`` gets
    ``"format": "csql-sim <command> report"`` and ``"version": 1`` (:func:`with_format`).

    Returns:
        The JSON file written, if any.
    """
    target = getattr(args, "json", None)
    if target is not None:
        if isinstance(doc, dict):
            doc = with_format(doc, report_format(args))
            if "provenance" not in doc:
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
    """The subcommand and every parameter it ran with (defaults included).

    A command with modes (``plan``: pairs and single plans, or PDDL problems) names with
    ``set_defaults(mode_options=f)`` the options that belong to a mode not running:
    ``f(args)``. They are refused when given in another mode, so they are left out.
    """
    mode_options = getattr(args, "mode_options", None)
    other = set(mode_options(args)) if mode_options is not None else set()
    return {k: v for k, v in vars(args).items() if k not in NOT_PARAMETERS and k not in other}


def default_path(args: argparse.Namespace, name: str, value: str) -> bool:
    """Fill in ``args.<name>`` with its default path when it was not given; True if so.

    Output options with a default path are registered with ``default=None`` so that a
    path the user named can be told from the default (:meth:`Outputs.file`'s ``default``).
    """
    if getattr(args, name, None) is not None:
        return False
    setattr(args, name, value)
    return True


def plan_outputs(args: argparse.Namespace) -> Outputs:
    """Declare every output of the command (its ``declare(args, outputs)`` and ``--json FILE``), check them all.

    Called by :func:`csql_sim.cli.main` before the command runs.

    Raises:
        OutputError: one line naming the first output that would fail or clobber a file.
    """
    outputs = Outputs(overwrite=getattr(args, "overwrite", False))
    declare = getattr(args, "declare", None)
    if declare is not None:
        declare(args, outputs)
    target = getattr(args, "json", None)
    if target not in (None, "-"):
        outputs.file(target, "JSON report", "json", option="--json")
    outputs.check()
    return outputs


@contextmanager
def json_stream(args: argparse.Namespace) -> Iterator[IO[str] | None]:
    """A text stream for JSON written piece by piece: stdout, or FILE renamed into place at the end.

    Yields None without ``--json``. A failed write of FILE (a full disk, a file-size
    limit) is a one-line OutputError naming it, and leaves nothing behind.
    """
    target = getattr(args, "json", None)
    if target is None:
        yield None
    elif target == "-":
        yield sys.stdout
    else:
        try:
            with atomic_output(target) as tmp, open(tmp, "w", encoding="utf-8") as fh:
                yield fh
        except OSError as exc:
            raise OutputError(f"cannot write JSON report {target!r} ({exc.strerror or exc}); nothing was written") \
                from None
        print(f"wrote {target}", file=sys.stderr)
