"""A command's outputs, declared together and checked before any work: :class:`Outputs`.

A command declares every file it will write (its ``--out``, ``--json``, ``--log``,
``--plot``, the sidecars and the files inside an output folder) and every file it reads;
:meth:`Outputs.check` then refuses, with one line naming the file, before the work starts:

* a path that cannot be written (a folder, a device, a read-only folder: :mod:`.files`);
* two outputs that are the same file, or an output that is the folder of another;
* an output that is one of the command's inputs (``show r.yaml --json r.yaml``);
* an existing file at a DEFAULT path (one the user did not name): never replaced unless
  ``--overwrite`` is given;
* an existing file at a path the user named that is not a csql-sim output of the same
  kind (:func:`is_ours`), unless ``--overwrite`` is given.

Paths are compared after resolving: the same file when ``os.path.samefile`` says so (both
exist), otherwise when their resolved absolute paths are equal.
"""

from __future__ import annotations

import os
import re
import stat
import zipfile
from dataclasses import dataclass
from pathlib import Path

from csql_sim.infra import files
from csql_sim.infra.files import OutputError, write_target

HEAD_BYTES = 4096
"""How much of an existing file is read to recognise it."""
KINDS = {"rules": "rule file", "transitions": "transition log", "json": "JSON report", "png": "PNG picture",
         "video": "video", "csv": "CSV table", "pddl": "PDDL file"}
"""The kinds of output and their names in messages."""
PDDL_HEADER = "; csql-sim"
"""The first characters of every PDDL file the tool writes (a PDDL comment)."""
PNG_TAG = b"csql-sim"
"""Found in a PNG's text chunk (``Software``) when the tool drew it."""
_JSON_FORMAT = re.compile(rb'\A\s*\{\s*"format"\s*:\s*"(csql-sim [^"\\]*)"')
_YAML_FORMAT = re.compile(rb"\A(?:\s*#[^\n]*\n)*\s*format:\s*['\"]?csql-sim rule base\b")
_NPZ_HEADER = "csql-sim rule base"


def read_head(path: str | os.PathLike) -> bytes | None:
    """The first :data:`HEAD_BYTES` bytes of a regular file, or None (not one, unreadable)."""
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


def _npz_is_rules(path: Path) -> bool:
    """Whether a zip file is an npz rule base: its ``header`` array names the format."""
    try:
        with zipfile.ZipFile(path) as archive, archive.open("header.npy") as member:
            header = member.read(1 << 16)
    except (OSError, KeyError, zipfile.BadZipFile, RuntimeError, ValueError):
        return False
    return any(_NPZ_HEADER.encode(codec) in header for codec in ("utf-32-le", "utf-32-be", "utf-8"))


def identify(path: str | os.PathLike) -> str | None:
    """The kind of csql-sim output a file is, read from its first bytes; None if not one.

    Rule files (YAML ``format: csql-sim rule base`` or an npz with that header), transition
    logs and JSON reports (``{"format": "csql-sim ..."`` first), PDDL files (first line
    :data:`PDDL_HEADER`) and PNGs (a text chunk with :data:`PNG_TAG`) say so themselves;
    videos and CSV tables do not (see :func:`is_ours`).
    """
    target = Path(path)
    head = read_head(target)
    if head is None:
        return None
    if head.startswith(b"\x89PNG"):
        return "png" if PNG_TAG in head else None
    if head.startswith(b"PK"):
        return "rules" if _npz_is_rules(target) else None
    if head.startswith(PDDL_HEADER.encode()):
        return "pddl"
    found = _JSON_FORMAT.match(head)
    if found:
        name = found.group(1).decode("utf-8", "replace")
        return "transitions" if name == "csql-sim transitions" else "rules" if name.startswith(_NPZ_HEADER) else "json"
    return "rules" if _YAML_FORMAT.match(head) else None


def is_ours(path: str | os.PathLike, kind: str, sidecar: str | os.PathLike | None = None) -> bool:
    """Whether the existing file ``path`` is a csql-sim output of ``kind``, which may be replaced.

    Either the file says so (:func:`identify`), or, for a file that cannot (a video, a
    CSV), its provenance ``sidecar`` (``<video>.json``, ``figure7.json``) is a csql-sim
    JSON report.
    """
    found = identify(path)
    if found == kind:
        return True
    return found is None and sidecar is not None and identify(sidecar) == "json"


def same_path(a: str | os.PathLike, b: str | os.PathLike) -> bool:
    """Whether two paths name the same file: ``samefile`` when both exist, else equal resolved paths."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)


def _inside(folder: str | os.PathLike, path: str | os.PathLike) -> bool:
    """Whether ``path`` lies (at any depth) inside ``folder``, after resolving both."""
    outer, inner = Path(os.path.realpath(folder)), Path(os.path.realpath(path))
    return outer != inner and outer in inner.parents


@dataclass(frozen=True)
class Output:
    """One output a command declared.

    Attributes:
        path: the path as given (or the default).
        what: its name in messages (``"rule file"``, ``"JSON report"``).
        kind: a key of :data:`KINDS`; None for a folder.
        default: True when the user did not name it (the command's default path).
        sidecar: the provenance JSON that vouches for a file that cannot say it is ours.
        option: the flag that names it (for the message: ``--out``, ``--json``).
    """

    path: Path
    what: str
    kind: str | None
    default: bool = False
    sidecar: Path | None = None
    option: str = "--out"

    @property
    def shown(self) -> str:
        """The path as messages show it."""
        return repr(os.fspath(self.path))


class Outputs:
    """The outputs and inputs of one command run, checked together by :meth:`check`.

    Args:
        overwrite: ``--overwrite``: existing files may be replaced whatever they are.
    """

    def __init__(self, overwrite: bool = False) -> None:
        self.overwrite = overwrite
        self.outputs: list[Output] = []
        self.inputs: list[tuple[Path, str]] = []

    def file(self, path: str | os.PathLike, what: str, kind: str, *, default: bool = False,
             sidecar: str | os.PathLike | None = None, option: str = "--out") -> Path:
        """Declare a file the command will write; returns it as a Path."""
        if kind not in KINDS:
            raise ValueError(f"unknown kind of output {kind!r}")
        _non_empty(path, what, option)
        self.outputs.append(Output(Path(path), what, kind, default, Path(sidecar) if sidecar else None, option))
        return Path(path)

    def folder(self, path: str | os.PathLike, what: str, *, default: bool = False, option: str = "--out") -> Path:
        """Declare a folder the command will write files into (declare those with :meth:`file`)."""
        _non_empty(path, what, option)
        self.outputs.append(Output(Path(path), what, None, default, None, option))
        return Path(path)

    def input(self, path: str | os.PathLike | None, what: str) -> None:
        """Declare a file the command reads (None: no such input this time)."""
        if path is not None:
            self.inputs.append((Path(path), what))

    def check(self) -> None:
        """Every check of the module docstring, before any work.

        Raises:
            OutputError: one line naming the first offending file.
        """
        for out in self.outputs:
            if out.kind is None:
                files.check_output_folder(out.path, out.what)
            else:
                files.check_output_file(out.path, out.what)
        self._check_clashes()
        for out in self.outputs:
            if out.kind is not None:
                self._check_replace(out)

    def _check_clashes(self) -> None:
        written = [out for out in self.outputs if out.kind is not None]
        for i, a in enumerate(self.outputs):
            for b in self.outputs[i + 1:]:
                if same_path(a.path, b.path):
                    raise OutputError(f"{a.what} {a.shown} and {b.what} {b.shown} are the same path; "
                                      f"give each output a path of its own")
            for b in written:
                if a.kind is not None and _inside(a.path, b.path):
                    raise OutputError(f"{a.what} {a.shown} would be a file, but {b.what} {b.shown} needs it "
                                      f"as a folder")
        for out in written:
            for path, what in self.inputs:
                if same_path(out.path, path):
                    raise OutputError(f"{out.what} {out.shown} is the {what} this command reads; "
                                      f"refusing to replace an input (give another {out.option})")

    def _check_replace(self, out: Output) -> None:
        """An existing file is replaced only if asked, or if it is ours and the user named it."""
        assert out.kind is not None
        target = write_target(out.path)
        if self.overwrite or not target.exists():
            return
        if out.default:
            raise OutputError(f"{out.what} {out.shown} already exists (the default {out.option}); "
                              f"name another with {out.option}, or give --overwrite to replace it")
        if not is_ours(target, out.kind, out.sidecar):
            vouch = f" (nor vouched for by a csql-sim {out.sidecar.name} beside it)" if out.sidecar is not None else ""
            raise OutputError(f"{out.what} {out.shown} exists and is not a csql-sim {KINDS[out.kind]}{vouch}; "
                              f"refusing to replace it (give --overwrite to replace it)")


def _non_empty(path: str | os.PathLike, what: str, option: str) -> None:
    if not os.fspath(path):
        raise OutputError(f"{what}: empty path ({option} '')")
