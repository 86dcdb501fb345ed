"""Guarded reads of input files: regular files only, size-capped; YAML and JSON with bounded nesting.

Every file the tool reads comes through :func:`read_text_file` (or :func:`read_bytes_file`),
YAML through :func:`load_yaml` (no aliases, bounded nesting) and JSON through
:func:`load_json`: nesting bounded by a linear scan before the parser runs (so its
recursion cannot overflow) and integers bounded in digits before they are converted (so
Python's 4,300-digit limit is never reached). Each refusal is one
:class:`InputFileError` line naming the source. :mod:`csql_sim.infra.files` imports these
names too.
"""

from __future__ import annotations

import errno
import itertools
import json
import os
import re
import stat

import yaml

from csql_sim.infra.errors import CsqlError

MAX_YAML_DEPTH = 32
"""The deepest nesting of lists and mappings a YAML input may have (rule files use 3)."""
MAX_JSON_DEPTH = 32
"""The deepest nesting of arrays and objects a JSON input may have (the tool's own files use 5 at most)."""
MAX_JSON_DIGITS = 1000
"""The most digits an integer in a JSON input may have (Python refuses more than 4,300)."""


class InputFileError(CsqlError):
    """An input file that is missing, not a regular file, too large or not valid YAML or JSON."""


def reason(exc: OSError) -> str:
    """Why an OS call failed, in words (``No such file or directory``)."""
    return exc.strerror or errno.errorcode.get(exc.errno or 0, exc.__class__.__name__)


def read_text_file(path: str | os.PathLike, max_bytes: int, what: str = "file") -> str:
    """Read a UTF-8 regular file of at most ``max_bytes`` bytes.

    Devices (``/dev/zero``), pipes and folders are refused without reading, and so is a
    file larger than the cap (before reading it).

    Raises:
        InputFileError: one line naming the file and the problem.
    """
    data = read_bytes_file(path, max_bytes, what)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputFileError(f"{os.fspath(path)}: not UTF-8 text (byte {exc.start})") from None


def read_bytes_file(path: str | os.PathLike, max_bytes: int, what: str = "file") -> bytes:
    """:func:`read_text_file`'s guarded read, for binary content (an ``.npz`` rule base)."""
    with InputFile(path, what) as source:
        return source.read_all(max_bytes)


class InputFile:
    """A regular input file opened once and read in two steps: its first bytes, then (its cap known) the rest.

    Devices, pipes and folders are refused when opened, without reading (opened without
    blocking, so a pipe is never waited on).

    Args:
        path: the file.
        what: what the file is, for messages (``rule file``).
        head_bytes: how many first bytes to read at once into :attr:`head`.

    Raises:
        InputFileError: one line naming the file and the problem.
    """

    def __init__(self, path: str | os.PathLike, what: str = "file", head_bytes: int = 0) -> None:
        self.shown, self.what = os.fspath(path), what
        try:
            fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
        except FileNotFoundError:
            raise InputFileError(f"{self.shown}: no such {what}") from None
        except OSError as exc:
            raise InputFileError(f"{self.shown}: cannot read {what} ({reason(exc)})") from None
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            os.close(fd)
            kind = "a folder" if stat.S_ISDIR(info.st_mode) else "a device, pipe or socket"
            raise InputFileError(f"{self.shown}: {kind}, not a regular {what}")
        self.size = info.st_size
        self._fd, self._file = fd, None
        self.head = self._read(head_bytes) if head_bytes else b""

    def _read(self, count: int) -> bytes:
        try:
            if self._file is None:  # opened as a Python file only when read from
                self._file = os.fdopen(self._fd, "rb")
            return self._file.read(count)
        except OSError as exc:
            self.close()
            raise InputFileError(f"{self.shown}: cannot read {self.what} ({reason(exc)})") from None

    def read_all(self, max_bytes: int, what: str | None = None) -> bytes:
        """The whole file (the head read already, then the rest), refused above ``max_bytes`` before reading on."""
        what = what or self.what
        if self.size > max_bytes:
            raise InputFileError(f"{self.shown}: {self.size:,} bytes, above the {max_bytes:,}-byte limit for a {what}")
        data = self.head + self._read(max_bytes + 1 - len(self.head))
        if len(data) > max_bytes:
            raise InputFileError(f"{self.shown}: above the {max_bytes:,}-byte limit for a {what}")
        return data

    def close(self) -> None:
        """Close the file (again: nothing)."""
        if self._file is not None:
            self._file.close()
        elif self._fd >= 0:
            os.close(self._fd)
        self._fd = -1

    def __enter__(self) -> InputFile:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


_C_LOADER = getattr(yaml, "CSafeLoader", None)
_OPEN = (yaml.SequenceStartEvent, yaml.MappingStartEvent)
_CLOSE = (yaml.SequenceEndEvent, yaml.MappingEndEvent)


def _check_events(text: str, source: str, max_depth: int) -> None:
    """Refuse aliases and deep nesting from the parser's events, before any node is built."""
    depth = 0
    for event in yaml.parse(text, Loader=_C_LOADER or yaml.SafeLoader):
        if isinstance(event, yaml.AliasEvent):
            line = event.start_mark.line + 1 if event.start_mark else "?"
            raise InputFileError(f"{source}: YAML aliases (*{event.anchor}) are not allowed (line {line})")
        if isinstance(event, _OPEN):
            depth += 1
            if depth > max_depth:
                line = event.start_mark.line + 1 if event.start_mark else "?"
                raise InputFileError(f"{source}: YAML nested deeper than {max_depth} levels (line {line})")
        elif isinstance(event, _CLOSE):
            depth -= 1


def load_yaml(text: str, source: str, max_depth: int = MAX_YAML_DEPTH) -> object:
    """Parse YAML safely: plain data only, no aliases, at most ``max_depth`` levels deep.

    Uses libyaml when PyYAML has it (about five times faster than the pure-Python loader).

    Raises:
        InputFileError: one line naming ``source`` and, where known, the line.
    """
    try:
        _check_events(text, source, max_depth)
        return yaml.load(text, Loader=_C_LOADER or yaml.SafeLoader)  # noqa: S506 (a safe loader)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark is not None else ""
        raise InputFileError(f"{source}: not valid YAML{where} (truncated or corrupt?)") from None


class _TooManyDigits(ValueError):
    """An integer in a JSON text with more digits than allowed."""


_JSON_STRING = re.compile(r'"[^"\\]*(?:\\[\s\S]?[^"\\]*)*(?:"|\Z)')
"""A JSON string, or an unterminated one up to the end (always matches at a quote: linear, no backtracking)."""
_NOT_BRACKET = re.compile(r"[^\[\]{}]+")
_STEP = {"[": 1, "{": 1, "]": -1, "}": -1}


def json_depth(text: str) -> int:
    """How deep the arrays and objects of a JSON text nest (brackets inside strings do not count); linear time."""
    if text.count("[") + text.count("{") == 0:
        return 0
    marks = _NOT_BRACKET.sub("", _JSON_STRING.sub("", text))
    return max(itertools.accumulate(map(_STEP.__getitem__, marks)), default=0)


def load_json(text: str, source: str, *, max_depth: int = MAX_JSON_DEPTH, max_digits: int = MAX_JSON_DIGITS) -> object:
    """Parse JSON input safely: at most ``max_depth`` levels deep, integers of at most ``max_digits`` digits.

    The nesting is measured by a linear scan before the parser runs, so the parser's
    recursion cannot overflow; integers are checked before they are converted.

    Raises:
        InputFileError: one line naming ``source`` and what is wrong.
    """
    if text.count("[") + text.count("{") > max_depth and json_depth(text) > max_depth:
        raise InputFileError(f"{source}: JSON nested deeper than {max_depth} levels")

    def parse_int(digits: str) -> int:
        if len(digits) - digits.startswith("-") > max_digits:
            raise _TooManyDigits(len(digits) - digits.startswith("-"))
        return int(digits)

    try:
        return json.loads(text, parse_int=parse_int)
    except _TooManyDigits as exc:
        raise InputFileError(f"{source}: an integer of {exc.args[0]:,} digits (at most {max_digits:,})") from None
    except json.JSONDecodeError as exc:
        raise InputFileError(f"{source} is not JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") \
            from None
    except (ValueError, RecursionError) as exc:
        raise InputFileError(f"{source} is not JSON ({exc.__class__.__name__})") from None


def read_json_file(path: str | os.PathLike, max_bytes: int, what: str = "JSON file") -> object:
    """Read a JSON regular file of at most ``max_bytes`` bytes with :func:`load_json`'s guards."""
    return load_json(read_text_file(path, max_bytes, what), os.fspath(path))
