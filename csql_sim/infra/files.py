"""Files in and out: output checks before work starts, atomic writes, guarded reads.

Every command that writes checks its outputs with :func:`check_output_file` or
:func:`check_output_folder` before any long work, writes with :func:`write_atomic`
(temporary file in the target's folder, then a rename) and, when a write fails at the end
anyway, keeps what it computed with :func:`write_or_keep`. Every file the tool reads comes
through :func:`read_text_file` (regular files only, size-capped), YAML through
:func:`load_yaml` and JSON through :func:`load_json` (bounded nesting, checked before the
parser runs): these live in :mod:`csql_sim.infra.reading` and are imported from here too.

Device nodes, pipes and sockets are never outputs: ``--out /dev/null`` is refused with a
one-line error (exit 2) instead of being replaced by a regular file. An output that is a
symbolic link is written through: the file it points to is replaced, the link is kept;
a command's own files inside its output folder are written with ``follow_links=False``
(a link there is replaced, never written through). Folders a write creates for its file
are removed again when the write fails or is interrupted (if they are still empty).

Temporary files are named ``.<name>.csql-sim-<pid>-<random>.tmp<suffix>`` beside their
target. They are removed when the write fails or the process is interrupted (the CLI
turns SIGTERM into an exception, so ``finally`` blocks run); a process killed outright
(SIGKILL) leaves its temporary file, which the next write of the same output removes once
the process that made it is gone (:func:`remove_stale_temporaries`).
"""

from __future__ import annotations

import os
import stat
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from csql_sim.infra.errors import CsqlError
from csql_sim.infra.reading import MAX_JSON_DEPTH as MAX_JSON_DEPTH
from csql_sim.infra.reading import MAX_YAML_DEPTH as MAX_YAML_DEPTH
from csql_sim.infra.reading import InputFileError as InputFileError
from csql_sim.infra.reading import load_json as load_json
from csql_sim.infra.reading import load_yaml as load_yaml
from csql_sim.infra.reading import read_bytes_file as read_bytes_file
from csql_sim.infra.reading import read_json_file as read_json_file
from csql_sim.infra.reading import read_text_file as read_text_file
from csql_sim.infra.reading import reason as _reason

RUN_STARTED = time.time()
"""When this process imported the module: temporary files older than this may be stale."""
TEMP_TAG = "csql-sim-"
"""The mark of our temporary files: ``.<name>.csql-sim-<pid>-<random>.tmp<suffix>``."""


class OutputError(CsqlError):
    """An output path that cannot be written (a folder, a device, a read-only folder)."""


def _mode(path: Path, shown: str, what: str) -> int | None:
    """The stat mode of ``path`` (following links), or None if nothing is there."""
    try:
        return path.stat().st_mode
    except (FileNotFoundError, NotADirectoryError):
        return None
    except OSError as exc:
        raise OutputError(f"{what} {shown}: cannot inspect {str(path)!r} ({_reason(exc)})") from None


def _nearest_existing(path: Path, shown: str, what: str) -> Path:
    """``path`` or its closest ancestor that exists (the folder a write would start from)."""
    probe = path
    while _mode(probe, shown, what) is None and probe != probe.parent:
        probe = probe.parent
    return probe


def _probe_folder(folder: Path, shown: str, what: str) -> None:
    """Create and remove a temporary file in ``folder``: the only test root cannot fool."""
    if not folder.is_dir():
        raise OutputError(f"{what} {shown}: {str(folder)!r} is not a folder")
    try:
        fd, name = tempfile.mkstemp(prefix=".csql-sim-probe-", dir=folder)
    except OSError as exc:
        raise OutputError(f"{what} {shown}: cannot write in {str(folder)!r} ({_reason(exc)})") from None
    os.close(fd)
    os.unlink(name)


def check_output_file(path: str | os.PathLike, what: str = "output file") -> Path:
    """Check, before any work, that ``path`` can be written as a regular file.

    Refuses an existing folder, device node, pipe or socket, a parent that is not a
    folder, and a folder the process cannot write in. Creates nothing (a probe file is
    created and removed in the nearest existing folder).

    Raises:
        OutputError: one line naming the path and the problem.
    """
    shown = repr(os.fspath(path))
    if not os.fspath(path):
        raise OutputError(f"{what}: empty path")
    target = Path(path)
    mode = _mode(target, shown, what)
    if mode is not None:
        if stat.S_ISDIR(mode):
            raise OutputError(f"{what} {shown} is a folder; give a file name")
        if not stat.S_ISREG(mode):
            raise OutputError(f"{what} {shown} is a device, pipe or socket, not a regular file; refusing to replace it")
    _probe_folder(_nearest_existing(target.parent.absolute(), shown, what), shown, what)
    return target


def check_output_folder(path: str | os.PathLike, what: str = "output folder") -> Path:
    """Check, before any work, that ``path`` is (or can be created as) a writable folder.

    Raises:
        OutputError: one line naming the path and the problem.
    """
    shown = repr(os.fspath(path))
    if not os.fspath(path):
        raise OutputError(f"{what}: empty path")
    target = Path(path)
    mode = _mode(target, shown, what)
    if mode is not None and not stat.S_ISDIR(mode):
        raise OutputError(f"{what} {shown} exists and is not a folder")
    _probe_folder(_nearest_existing(target.absolute(), shown, what), shown, what)
    return target


def _refuse_special(target: Path, follow_links: bool = True) -> None:
    """Refuse a folder, device, pipe or socket at ``target`` (a link itself is fine when not following)."""
    try:
        mode = target.stat().st_mode if follow_links else target.lstat().st_mode
    except OSError:
        return
    if stat.S_ISDIR(mode):
        raise OutputError(f"{str(target)!r} is a folder, not a regular file; refusing to replace it")
    if not (stat.S_ISREG(mode) or stat.S_ISLNK(mode)):
        raise OutputError(f"{str(target)!r} is a device, pipe or socket, not a regular file; refusing to replace it")


def write_target(path: str | os.PathLike) -> Path:
    """The file a write of ``path`` replaces: ``path`` itself, or the file a symbolic link points to."""
    target = Path(path)
    return Path(os.path.realpath(target)) if target.is_symlink() else target


def _temp_owner(entry: str, prefix: str, suffix: str) -> int | None:
    """The pid in the name of one of our temporary files of an output, or None for any other name."""
    if not (entry.startswith(prefix) and entry.endswith(suffix)):
        return None
    pid = entry[len(prefix):].split("-", 1)[0]
    return int(pid) if pid.isdigit() else None


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # another user's process: alive
        return True
    return True


def remove_stale_temporaries(path: str | os.PathLike) -> list[Path]:
    """Remove the temporary files a killed earlier write of ``path`` left beside it.

    Only files named as :func:`atomic_output` names them for this very output, older than
    this process and made by a process that is gone, are removed; errors are ignored.

    Returns:
        The files removed.
    """
    target = Path(path)
    prefix, suffix = f".{target.name}.{TEMP_TAG}", f".tmp{target.suffix}"
    removed = []
    try:
        entries = list(os.scandir(target.parent))
    except OSError:
        return removed
    for entry in entries:
        pid = _temp_owner(entry.name, prefix, suffix)
        if pid is None or _alive(pid):
            continue
        try:
            if entry.is_file(follow_symlinks=False) and entry.stat(follow_symlinks=False).st_mtime < RUN_STARTED:
                os.unlink(entry.path)
                removed.append(Path(entry.path))
        except OSError:
            continue
    return removed


def _publish(tmp: Path, target: Path) -> None:
    """Sync ``tmp``, give it an ordinary new file's permissions and rename it onto ``target``."""
    with open(tmp, "rb+") as fh:
        os.fsync(fh.fileno())
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    os.replace(tmp, target)


def _missing_folders(folder: Path) -> list[Path]:
    """``folder`` and its ancestors that do not exist yet (the ones a write creates), deepest first."""
    missing, probe = [], folder
    while not os.path.lexists(probe) and probe != probe.parent:
        missing.append(probe)
        probe = probe.parent
    return missing


def remove_folders(created: list[Path]) -> None:
    """Remove the folders a failed write created (deepest first), each only while it is empty."""
    for folder in created:
        try:
            folder.rmdir()
        except OSError:
            return


@contextmanager
def atomic_output(path: str | os.PathLike, *, follow_links: bool = True) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; on success it is renamed onto ``path``.

    The caller writes the temporary file by any means (an encoder, a plotting library);
    it keeps the target's suffix, so writers that pick a format by suffix still work.
    If the block raises (SIGTERM included, see :mod:`csql_sim.cli`), the temporary file is
    removed, ``path`` is left as it was and the folders created for it are removed again
    (while empty). On success the file is synced to disk and gets the permissions an
    ordinary new file would (0666 less the umask), not mkstemp's 0600, before the rename.
    A path that is a folder, device, pipe or socket is refused (OutputError) rather than
    replaced; a symbolic link is written through (:func:`write_target`), or with
    ``follow_links=False`` replaced by the new file. Stale temporary files of the same
    output are removed first.
    """
    target = write_target(path) if follow_links else Path(path)
    _refuse_special(target, follow_links)
    created, tmp = _missing_folders(target.parent), None
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        remove_stale_temporaries(target)
        fd, name = tempfile.mkstemp(prefix=f".{target.name}.{TEMP_TAG}{os.getpid()}-",
                                    suffix=f".tmp{target.suffix}", dir=target.parent)
        os.close(fd)
        tmp = Path(name)
        yield tmp
        _publish(tmp, target)
    except BaseException:
        if tmp is not None:
            tmp.unlink(missing_ok=True)
        else:  # a signal inside mkstemp, after it made the file but before it named it
            _remove_own_temporaries(target)
        remove_folders(created)
        raise


def _remove_own_temporaries(target: Path) -> None:
    """Remove this process's temporary files of ``target`` (named as :func:`atomic_output` names them)."""
    prefix, suffix = f".{target.name}.{TEMP_TAG}{os.getpid()}-", f".tmp{target.suffix}"
    try:
        entries = list(os.scandir(target.parent))
    except OSError:
        return
    for entry in entries:
        if entry.name.startswith(prefix) and entry.name.endswith(suffix):
            try:
                os.unlink(entry.path)
            except OSError:
                pass


def write_atomic(path: str | os.PathLike, data: str | bytes, *, follow_links: bool = True) -> Path:
    """Write ``data`` (text as UTF-8) to ``path``; a crash leaves either the old file or the new one.

    With ``follow_links=False`` a symbolic link at ``path`` is replaced, not written through.
    """
    with atomic_output(path, follow_links=follow_links) as tmp:
        tmp.write_bytes(data.encode("utf-8") if isinstance(data, str) else data)
    return Path(path)


def _keep(name: str, data: str | bytes) -> str | None:
    """Save ``data`` in the system's temporary folder; its path, or None if that fails too.

    A copy that cannot be written whole (a full disk, a file-size limit) is removed: what
    is kept is complete or does not exist.
    """
    kept = None
    try:
        fd, kept = tempfile.mkstemp(prefix="csql-sim-", suffix=f"-{name}")
        with os.fdopen(fd, "wb") as fh:
            fh.write(data.encode("utf-8") if isinstance(data, str) else data)
            fh.flush()
            os.fsync(fh.fileno())
    except OSError:
        if kept is not None:
            try:
                os.unlink(kept)
            except OSError:
                pass
        return None
    return kept


def write_or_keep(outputs: list[tuple[str | os.PathLike, str | bytes]]) -> list[Path]:
    """Write every ``(path, data)`` atomically; whatever fails is kept in the temporary folder.

    A failed write leaves its target as it was and no temporary file beside it; a copy
    kept in the temporary folder is complete, or is not there at all.

    Returns:
        The paths written.

    Raises:
        OutputError: one line naming the first failed path, why, and where each failed
            output was kept instead (or that no copy could be kept).
    """
    written, kept, lost, first = [], [], [], None
    for path, data in outputs:
        try:
            written.append(write_atomic(path, data))
        except (OSError, OutputError) as exc:
            first = first or (os.fspath(path), _reason(exc) if isinstance(exc, OSError) else str(exc))
            copy = _keep(Path(path).name, data)
            if copy is None:
                lost.append(Path(path).name)
            else:
                kept.append(copy)
    if first is None:
        return written
    where = [f"the results are kept in {', '.join(kept)}"] if kept else []
    if lost:
        where.append(f"no copy of {', '.join(lost)} could be kept either")
    raise OutputError(f"cannot write {first[0]!r} ({first[1]}); {'; '.join(where)}")
