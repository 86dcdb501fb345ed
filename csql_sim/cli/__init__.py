"""The ``csql-sim`` command line: a thin layer over the library.

Each subcommand lives in a small module with a ``register(subparsers)`` function; the
handlers call library functions and raise :class:`csql_sim.infra.errors.CsqlError` for bad
input, which :func:`main` prints as one line before exiting with status 2.

:func:`main` also

* checks every output of the command before it runs (:func:`csql_sim.cli.output.plan_outputs`);
* turns SIGTERM into an exception (:class:`Terminated`), so that temporary files are
  removed and worker processes stopped as on Ctrl-C (exit status 143);
* prints every error as one line, ``csql-sim <command>: error: ...`` (``csql-sim: error:``
  without a command);
* turns a failed write to stdout (``> /dev/full``) into one line (exit status 2), and
  writes what stdout's encoding cannot show as backslash escapes instead of failing.
"""

from __future__ import annotations

import argparse
import contextlib
import gc
import importlib
import io
import os
import signal
import sys
import threading
import traceback
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, NoReturn

from csql_sim import __version__
from csql_sim.cli.args import refuse_ignored, say
from csql_sim.cli.output import plan_outputs
from csql_sim.infra.errors import CsqlError, Terminated
from csql_sim.infra.outputs import Outputs

TERMINATED_STATUS = 128 + signal.SIGTERM


class StdoutError(CsqlError):
    """Standard output could not be written (a full disk, a closed terminal)."""


class _GuardedStdout:
    """sys.stdout, but a failed write or flush raises :class:`StdoutError` (a broken pipe stays one)."""

    def __init__(self, stream: Any) -> None:
        self._stream = stream

    def _guard(self, name: str, *args: Any) -> Any:
        try:
            return getattr(self._stream, name)(*args)
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise StdoutError(f"cannot write to standard output ({exc.strerror or exc})") from None

    def write(self, text: str) -> int:  # noqa: D102
        return self._guard("write", text)

    def writelines(self, lines: Any) -> None:  # noqa: D102
        self._guard("writelines", lines)

    def flush(self) -> None:  # noqa: D102
        self._guard("flush")

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


class _ClosedStdout(io.TextIOBase):
    """Standard output when the command was started with it closed (``>&-``): nothing is written to it.

    :func:`main` refuses such a command before any work, in one line (exit 2), so that no
    file is written by a command whose report could not be shown.
    """

    def writable(self) -> bool:  # noqa: D102
        return True

    def write(self, text: str) -> int:  # noqa: D102
        return len(text)

    def fileno(self) -> int:  # noqa: D102
        raise io.UnsupportedOperation("standard output is closed")


SUBCOMMANDS = {
    "core": ("states", "rules", "plan"), "learn": ("experiment", "train", "scaling", "bench", "params"),
    "rulefile": ("show", "prune"), "lifted": ("train-lifted",), "sim": ("render", "evaluate"), "demo": ("demo",),
    "discover": ("discover",), "pddl_cmd": ("pddl",), "problems_cmd": ("problems",), "execute": ("execute",),
    "generalize": ("generalize",), "validate_cmd": ("validate",),
}
"""Each module of ``csql_sim.cli`` with a ``register(subparsers)``, and the subcommands it registers, in help order."""


class OneLineParser(argparse.ArgumentParser):
    """An ArgumentParser whose usage errors are one line on stderr and exit status 2."""

    def error(self, message: str) -> None:  # noqa: D102
        one_line = " ".join(message.split())
        self.exit(2, f"{self.prog}: error: {one_line} (see --help)\n")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The full parser with every subcommand registered; with ``command``, only the module registering it.

    A command's run imports its own module alone (:data:`SUBCOMMANDS`): not the others' libraries
    (training, video) that their options read. An unknown ``command`` gets the full parser.
    """
    parser = OneLineParser(
        prog="csql-sim",
        description="Classifier-system Q-learning on the blocks world, executed on a simulated arm.",
    )
    parser.add_argument("--version", action="version", version=f"csql-sim {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=OneLineParser)
    modules = [name for name, commands in SUBCOMMANDS.items() if command in commands] or list(SUBCOMMANDS)
    for name in modules:
        importlib.import_module(f"csql_sim.cli.{name}").register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the console script; returns the exit status."""
    closed = _reserve_standard_streams()
    words = sys.argv[1:] if argv is None else argv
    args = build_parser(words[0] if words else None).parse_args(argv)
    with _on_sigterm_raise() as sigterm, _guarded_stdout():
        outputs = None
        try:
            if closed is not None:  # refused before any work: nothing written, nothing lost
                raise StdoutError("standard output is closed (>&-); send it somewhere, e.g. >/dev/null")
            refuse_ignored(args)
            outputs = plan_outputs(args)
            status = int(args.func(args) or 0)
            sys.stdout.flush()
            return status
        except CsqlError as exc:
            kept = _written(outputs) if isinstance(exc, StdoutError) and outputs is not None else []
            say(args, "error", f"{exc}; the files it wrote are kept: {', '.join(kept)}" if kept else str(exc))
            if isinstance(exc, StdoutError):
                _silence_stdout()
            return 2
        except BrokenPipeError:
            # The reader (e.g. `| head`) closed the pipe: stop quietly, as Unix tools do.
            _silence_stdout()
            return 0
        except KeyboardInterrupt as exc:  # Ctrl-C, or SIGTERM (Terminated, or what Ray made of it)
            _close_progress_bars()
            terminated = isinstance(exc, Terminated) or sigterm.received
            print(f"csql-sim: {'terminated' if terminated else 'interrupted'}{_note(exc)}", file=sys.stderr)
            return TERMINATED_STATUS if terminated else 130


def console() -> NoReturn:
    """The console script and ``python -m csql_sim``: :func:`main`'s status is the exit status.

    After a Ray session the process ends without the interpreter's finalization, in which
    Ray's C++ threads, still running after ``ray.shutdown``, crashed (SIGSEGV after Ctrl-C);
    whatever ends :func:`main` then (``SystemExit``, a second Ctrl-C, a bug's traceback)
    sets the status instead of reaching the finalization. Otherwise every object left is
    frozen (``gc.freeze``) before the exit: the finalization's garbage collection then skips
    them (after the deadlock kernels were loaded, numba's objects took about 0.4 CPU s to
    collect); what the command wrote is closed and flushed by then.
    """
    try:
        status = main()
    except BaseException as exc:
        if "ray" not in sys.modules:
            raise
        status = _status_of(exc)
    if "ray" in sys.modules:
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
        os._exit(status)
    gc.freeze()  # the interpreter's exit then skips collecting what the command leaves (numba's: about 0.4 CPU s)
    sys.exit(status)


def _status_of(exc: BaseException) -> int:
    """The exit status the interpreter would give for ``exc`` escaping; a bug's traceback is printed."""
    if isinstance(exc, SystemExit):
        if exc.code is None or isinstance(exc.code, int):
            return exc.code or 0
        print(exc.code, file=sys.stderr)
        return 1
    if isinstance(exc, KeyboardInterrupt):
        return TERMINATED_STATUS if isinstance(exc, Terminated) else 130
    traceback.print_exception(exc)
    return 1


def _written(outputs: Outputs) -> list[str]:
    """The declared output files that exist now (after a failed write to stdout: what the command did write)."""
    return [os.fspath(out.path) for out in outputs.outputs if out.kind is not None and os.path.isfile(out.path)]


def _reserve_standard_streams() -> _ClosedStdout | None:
    """Make a closed stdin, stdout or stderr (``>&-``) harmless; the stand-in for a closed stdout, if any.

    Each closed descriptor 0-2 is opened on ``/dev/null``, so that no file the command
    opens takes its number (a C library or a child process writing to "stdout" would
    write into it). A closed stderr becomes ``/dev/null`` (the exit status still tells);
    a closed stdout becomes a :class:`_ClosedStdout` (the command is then refused).
    """
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:
            null = os.open(os.devnull, os.O_RDWR)
            if null != fd:
                os.dup2(null, fd)
                os.close(null)
    if sys.stderr is None:
        sys.stderr = open(os.devnull, "w")  # noqa: SIM115 (for the life of the process)
    if sys.stdout is None:
        sys.stdout = _ClosedStdout()
    return sys.stdout if isinstance(sys.stdout, _ClosedStdout) else None


def _note(exc: KeyboardInterrupt) -> str:
    """What a command said about its interruption (e.g. how to resume), as ``: note``; empty if nothing."""
    note = exc.args[0] if exc.args and isinstance(exc.args[0], str) else ""
    return f": {' '.join(note.split())}" if note else ""


class _SigtermRaises:
    """SIGTERM's handler while a command runs: raises :class:`Terminated` and remembers that it came.

    A forked worker inherits the handler; there it restores the default and dies by the
    signal, as it would have without the handler. A second SIGTERM while the first unwinds
    is ignored, so that it cannot cut the cleanup short (SIGKILL still ends the process).
    Ray turns the exception, raised inside ``ray.wait``, into a plain KeyboardInterrupt:
    :attr:`received` still tells :func:`main` that it was SIGTERM.
    """

    csql_sim_terminate = True  # what _default_sigterm_in_child looks for

    def __init__(self) -> None:
        self.me = os.getpid()
        self.received = False

    def __call__(self, signum: int, _frame: object) -> None:
        if os.getpid() != self.me:
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        self.received = True
        signal.signal(signum, signal.SIG_IGN)
        raise Terminated


@contextmanager
def _on_sigterm_raise() -> Iterator[_SigtermRaises]:
    """While the command runs, SIGTERM raises :class:`Terminated` in this process (main thread only)."""
    handler = _SigtermRaises()
    if threading.current_thread() is not threading.main_thread():
        yield handler
        return
    previous = signal.signal(signal.SIGTERM, handler)
    try:
        yield handler
    finally:
        signal.signal(signal.SIGTERM, previous)


def _default_sigterm_in_child() -> None:
    """After a fork: a worker dies by SIGTERM at once, as without :func:`_on_sigterm_raise`."""
    if getattr(signal.getsignal(signal.SIGTERM), "csql_sim_terminate", False):
        try:
            signal.signal(signal.SIGTERM, signal.SIG_DFL)
        except ValueError:  # not the main thread
            pass


os.register_at_fork(after_in_child=_default_sigterm_in_child)


@contextmanager
def _guarded_stdout() -> Iterator[None]:
    """Replace sys.stdout by a :class:`_GuardedStdout`; text it cannot encode is escaped, not an error."""
    stream = sys.stdout
    errors = getattr(stream, "errors", None)
    _set_errors(stream, "backslashreplace")
    sys.stdout = _GuardedStdout(stream)
    try:
        yield
    finally:
        if isinstance(sys.stdout, _GuardedStdout):
            sys.stdout = stream
        if errors is not None:
            _set_errors(stream, errors)


def _set_errors(stream: Any, errors: str) -> None:
    try:
        stream.reconfigure(errors=errors)
    except (AttributeError, ValueError, OSError):
        pass


def _silence_stdout() -> None:
    """Point stdout at /dev/null, so that the interpreter's last flush cannot fail again."""
    try:
        fileno = sys.stdout.fileno()
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, fileno)
        os.close(devnull)
    except (OSError, ValueError):
        pass


def _close_progress_bars() -> None:
    """End every open progress bar's line, so that a message after it starts a line of its own."""
    tqdm = sys.modules.get("tqdm")
    if tqdm is None:
        return
    for bar in list(getattr(tqdm.tqdm, "_instances", ())):
        bar.close()


if __name__ == "__main__":
    console()
