"""A command's outputs, declared together and checked before any work: :class:`Outputs`.

A command declares every file it will write (its ``--out``, ``--json``, ``--log``,
``--plot``, the sidecars and the files inside an output folder) and every file it reads;
:meth:`Outputs.check` then refuses, with one line naming the file, before the work starts:

* a path that cannot be written (a folder, a device, a read-only folder: :mod:`.files`);
* two outputs that are the same file, or an output that is the folder of another;
* an output that is one of the command's inputs (``show r.yaml --json r.yaml``);
* an existing file, whatever it is and whether the user named it or not, unless
  ``--overwrite`` is given (``train --resume`` continues its own directory without it);
* a trained model or rule file of any kind, or a file inside a sharded rule base's
  directory (:func:`csql_sim.infra.formats.model_kind`), as the path of a report, a picture,
  a video or a log: never, even with ``--overwrite``.

Paths are compared after resolving: the same file when ``os.path.samefile`` says so (both
exist), otherwise when their resolved absolute paths are equal.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from csql_sim.infra import files, formats
from csql_sim.infra.files import OutputError, write_target

KINDS = {"rules": "rule file or model", "transitions": "transition log", "json": "JSON report", "png": "PNG picture",
         "video": "video", "csv": "CSV table", "pddl": "PDDL file"}
"""The kinds of output and their names in messages; "rules" covers every model format (:mod:`.formats`)."""
PDDL_HEADER = "; csql-sim"
"""The first characters of every PDDL file the tool writes (a PDDL comment)."""
PNG_TAG = b"csql-sim"
"""Found in a PNG's text chunk (``Software``) when the tool drew it (provenance)."""


def same_path(a: str | os.PathLike, b: str | os.PathLike) -> bool:
    """Whether two paths name the same file: ``samefile`` when both exist, else equal resolved paths."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)


def _key(path: str | os.PathLike) -> tuple:
    """What :func:`same_path` compares, as a dict key: the file's device and inode, else the resolved path."""
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return ("path", os.path.realpath(path))
    return ("inode", st.st_dev, st.st_ino)


@dataclass(frozen=True)
class Output:
    """One output a command declared.

    Attributes:
        path: the path as given (or the default).
        what: its name in messages (``"rule file"``, ``"JSON report"``).
        kind: a key of :data:`KINDS`; None for a folder.
        default: True when the user did not name it (the command's default path).
        option: the flag that names it (for the message: ``--out``, ``--json``).
    """

    path: Path
    what: str
    kind: str | None
    default: bool = False
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
             option: str = "--out") -> Path:
        """Declare a file the command will write; returns it as a Path."""
        if kind not in KINDS:
            raise ValueError(f"unknown kind of output {kind!r}")
        _non_empty(path, what, option)
        self.outputs.append(Output(Path(path), what, kind, default, option))
        return Path(path)

    def folder(self, path: str | os.PathLike, what: str, *, default: bool = False, option: str = "--out") -> Path:
        """Declare a folder the command will write files into (declare those with :meth:`file`)."""
        _non_empty(path, what, option)
        self.outputs.append(Output(Path(path), what, None, default, option))
        return Path(path)

    def input(self, path: str | os.PathLike | None, what: str) -> None:
        """Declare a file the command reads (None: no such input this time)."""
        if path is not None:
            self.inputs.append((Path(path), what))

    def input_folder(self, folder: str | os.PathLike | None, what: str, pattern: str = "*.pddl") -> None:
        """Declare every file of ``folder`` matching ``pattern`` as an input (None: no such input this time)."""
        if folder is not None and os.path.isdir(folder):
            for path in sorted(Path(folder).glob(pattern)):
                self.inputs.append((path, what))

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
        """Outputs that are one file, a file another needs as its folder, an input: linear in their number.

        Each path is keyed by the file it names (device and inode when it exists, else its
        resolved path, as :func:`same_path` compares), so one pass over a dict finds them all.
        """
        seen: dict[tuple, Output] = {}
        for out in self.outputs:
            first = seen.setdefault(_key(out.path), out)
            if first is not out:
                raise OutputError(f"{first.what} {first.shown} and {out.what} {out.shown} are the same path; "
                                  f"give each output a path of its own")
        files_at = {os.path.realpath(out.path): out for out in self.outputs if out.kind is not None}
        for b in self.outputs:
            if b.kind is None:
                continue
            for parent in Path(os.path.realpath(b.path)).parents:
                a = files_at.get(os.fspath(parent))
                if a is not None:
                    raise OutputError(f"{a.what} {a.shown} would be a file, but {b.what} {b.shown} needs it "
                                      f"as a folder")
        inputs = {_key(path): what for path, what in self.inputs}
        for out in self.outputs:
            what = inputs.get(_key(out.path)) if out.kind is not None else None
            if what is not None:
                raise OutputError(f"{out.what} {out.shown} is the {what} this command reads; "
                                  f"refusing to replace an input, even with --overwrite (give another {out.option})")

    def _check_replace(self, out: Output) -> None:
        """An existing file is replaced only with ``--overwrite``, and a model never by anything but a model."""
        assert out.kind is not None
        target = write_target(out.path)
        if not target.exists():
            if os.path.lexists(out.path) and not self.overwrite:  # a dangling link: never followed unasked
                raise OutputError(f"{out.what} {out.shown} ({out.option}) is a link to nothing; give --overwrite "
                                  f"to write through it, or another {out.option}")
            return
        model = formats.model_kind(target) if out.kind != "rules" else None
        if model is not None:
            raise OutputError(f"{out.what} {out.shown} is {model}; a model is never replaced by a {KINDS[out.kind]}, "
                              f"even with --overwrite (give another {out.option})")
        if not self.overwrite:
            where = f"the default {out.option}" if out.default else out.option
            raise OutputError(f"{out.what} {out.shown} ({where}) already exists; give --overwrite to replace it, "
                              f"or another {out.option}")


def _non_empty(path: str | os.PathLike, what: str, option: str) -> None:
    if not os.fspath(path):
        raise OutputError(f"{what}: empty path ({option} '')")
