"""Argument types shared by the subcommands (argparse turns their errors into one line)."""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

from csql_sim.core.large_state import MAX_LARGE
from csql_sim.core.world import MAX_BLOCKS, MIN_BLOCKS

if TYPE_CHECKING:
    from csql_sim.infra.backends import Backend


def int_type(minimum: int, maximum: int | None = None) -> Callable[[str], int]:
    """An argparse type accepting integers in ``[minimum, maximum]`` (no upper bound if None)."""
    if maximum is not None:
        what = f"an integer {minimum}..{maximum}"
    else:
        what = {0: "a non-negative integer", 1: "a positive integer"}.get(minimum, f"an integer >= {minimum}")

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be {what}, got {text!r}") from None
        if value < minimum or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f"must be {what}, got {value}")
        return value

    return parse


positive_int = int_type(1)
non_negative_int = int_type(0)
blocks_arg = int_type(MIN_BLOCKS, MAX_BLOCKS)
large_blocks_arg = int_type(MIN_BLOCKS, MAX_LARGE)
"""``--blocks`` of the commands that take relational states past six blocks: an integer 2..26."""
seed_arg = non_negative_int
"""Seeds are non-negative integers (numpy's SeedSequence refuses negative ones)."""


def threshold_arg(text: str) -> float:
    """Argparse type for a strength threshold: a number in [0, 1] (strengths are at most 1)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number in [0, 1], got {text!r}") from None
    if not 0.0 <= value <= 1.0:  # also refuses nan
        raise argparse.ArgumentTypeError(f"must be a number in [0, 1], got {text}")
    return value


def add_quiet(parser: argparse.ArgumentParser) -> None:
    """The one progress flag of every command: ``--quiet`` (``--no-progress`` is an alias)."""
    parser.add_argument("--quiet", "--no-progress", dest="quiet", action="store_true",
                        help="no progress bars (shown only when stderr is a terminal anyway)")


def show_progress(args: argparse.Namespace) -> bool:
    """Progress bars only when stderr is a terminal and --quiet was not given."""
    return not getattr(args, "quiet", False) and sys.stderr.isatty()


def warn_workers(workers: int | None) -> None:
    """One warning line on stderr when ``--workers`` asks for more processes than cores."""
    cores = os.cpu_count() or 1
    if workers is not None and workers > cores:
        print(f"csql-sim: warning: --workers {workers} is more than the {cores} cores; using {cores}",
              file=sys.stderr)


def path_arg(text: str) -> str:
    """Argparse type of every file or folder argument: any path but the empty one."""
    if not text:
        raise argparse.ArgumentTypeError("empty path; give a file name")
    return text


def add_overwrite(parser: argparse.ArgumentParser) -> None:
    """``--overwrite``: replace existing output files whatever they are (added once per parser).

    Without it a command refuses to replace a file at a default output path, and a file at
    a path the user named unless it is a csql-sim output of the same kind
    (:mod:`csql_sim.infra.outputs`).
    """
    if "--overwrite" in parser._option_string_actions:
        return
    parser.add_argument("--overwrite", action="store_true",
                        help="replace existing output files (default: refuse a file at a default path, and a "
                             "named file that is not a csql-sim output of the same kind)")


def add_json(parser: argparse.ArgumentParser) -> None:
    """``--json [FILE]``: JSON instead of text, to FILE or (without one) to stdout; sets ``args.json``.

    ``args.json`` is None without the flag, ``"-"`` for stdout, or the file name. Adds
    ``--overwrite`` too (:func:`add_overwrite`).
    """
    parser.add_argument("--json", nargs="?", const="-", default=None, metavar="FILE", type=path_arg,
                        help="JSON instead of text: to FILE if given, otherwise to stdout")
    add_overwrite(parser)


def add_workers(parser: argparse.ArgumentParser, what: str = "processes") -> None:
    """``--workers K``; the default (None) is the number of cores capped at the number of tasks."""
    parser.add_argument("--workers", type=positive_int, default=None,
                        help=f"{what} (default: the number of cores, at most one per task)")


def add_seed(parser: argparse.ArgumentParser, what: str) -> None:
    """``--seed S`` (a non-negative integer, default 0)."""
    parser.add_argument("--seed", type=seed_arg, default=0, help=f"{what} (default 0)")


def add_backend_arguments(parser: argparse.ArgumentParser) -> None:
    """Add ``--backend processes|ray`` and ``--address ADDR`` to a subcommand."""
    parser.add_argument("--backend", choices=("processes", "ray"), default="processes",
                        help="where tasks run: a local process pool (default) or Ray")
    parser.add_argument("--address", help="with --backend ray: a running Ray cluster, e.g. 'auto' on one of its "
                        "nodes (default: start a local Ray instance)")


def backend_from_args(args: argparse.Namespace) -> Backend:
    """The :class:`csql_sim.infra.backends.Backend` of ``--backend``, ``--address`` and ``--workers``."""
    from csql_sim.infra.backends import Backend

    return Backend(args.backend, getattr(args, "workers", None), args.address)


def add_renderer_argument(parser: argparse.ArgumentParser) -> None:
    """Add ``--renderer tiny|egl|auto`` (the video renderer) to a subcommand."""
    parser.add_argument("--renderer", choices=("auto", "tiny", "egl"), default="auto",
                        help="video renderer: pybullet's TinyRenderer, its EGL plugin (OpenGL; a GPU where "
                        "there is one), or auto (default): EGL when its plugin loads")
