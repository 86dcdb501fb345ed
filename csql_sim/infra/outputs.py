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
  kind (:func:`is_ours`), unless ``--overwrite`` is given;
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
from csql_sim.infra.formats import read_head

KINDS = {"rules": "rule file or model", "transitions": "transition log", "json": "JSON report", "png": "PNG picture",
         "video": "video", "csv": "CSV table", "pddl": "PDDL file"}
"""The kinds of output and their names in messages; "rules" covers every model format (:mod:`.formats`)."""
PDDL_HEADER = "; csql-sim"
"""The first characters of every PDDL file the tool writes (a PDDL comment)."""
PNG_TAG = b"csql-sim"
"""Found in a PNG's text chunk (``Software``) when the tool drew it."""


def identify(path: str | os.PathLike) -> str | None:
    """The kind of csql-sim output a file is, read from its first bytes; None if not one.

    Rule files and models (every format of :data:`formats.MODEL_FORMATS`), transition
    logs and JSON reports name their format (:func:`formats.sniff`); PDDL files start with
    :data:`PDDL_HEADER` and PNGs carry :data:`PNG_TAG` in a text chunk; videos and CSV
    tables do not say (see :func:`is_ours`).
    """
    head = read_head(path)
    if head is None:
        return None
    if head.startswith(b"\x89PNG"):
        return "png" if PNG_TAG in head else None
    if head.startswith(PDDL_HEADER.encode()):
        return "pddl"
    name = formats.sniff(path)
    if name is None or not name.startswith("csql-sim"):
        return None
    return "rules" if name in formats.MODEL_FORMATS else "transitions" if name == formats.TRANSITIONS else "json"


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
        if not target.exists():
            return
        model = formats.model_kind(target) if out.kind != "rules" else None
        if model is not None:
            raise OutputError(f"{out.what} {out.shown} is {model}; a model is never replaced by a {KINDS[out.kind]}, "
                              f"even with --overwrite (give another {out.option})")
        if self.overwrite:
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
