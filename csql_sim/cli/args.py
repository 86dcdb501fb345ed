"""Argument types shared by the subcommands (argparse turns their errors into one line)."""

from __future__ import annotations

import argparse
import os
import sys
import textwrap
from collections.abc import Callable
from typing import TYPE_CHECKING

from csql_sim.core.files.pddl_import import MAX_DRAWN_BLOCKS
from csql_sim.core.state.state import MAX_LETTERS
from csql_sim.core.state.world import MAX_BLOCKS, MIN_BLOCKS
from csql_sim.infra.errors import CsqlError

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
large_blocks_arg = int_type(MIN_BLOCKS, MAX_LETTERS)
"""``--blocks`` of the commands that take relational states past six blocks: an integer 2..26."""
drawn_blocks_arg = int_type(MIN_BLOCKS, MAX_DRAWN_BLOCKS)
"""``--blocks`` of drawn problems (``csql-sim problems``): an integer 2..MAX_DRAWN_BLOCKS."""
seed_arg = non_negative_int
"""Seeds are non-negative integers (numpy's SeedSequence refuses negative ones)."""


def sizes_type(item: Callable[[str], int]) -> Callable[[str], list[int]]:
    """An argparse type for ``N`` or ``N,N,...``, each checked by ``item``."""

    def parse(text: str) -> list[int]:
        return [item(part) for part in text.split(",")]

    return parse


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


def prefix(args: argparse.Namespace | None) -> str:
    """``csql-sim <command>``: how every line the command line says about a command starts."""
    command = getattr(args, "command", None)
    return f"csql-sim {command}" if command else "csql-sim"


def say(args: argparse.Namespace | None, kind: str, text: str) -> None:
    """One line on stderr: ``csql-sim <command>: <kind>: <text>`` (``kind``: ``error`` or ``warning``)."""
    print(f"{prefix(args)}: {kind}: {' '.join(str(text).split())}", file=sys.stderr)


def warn_workers(args: argparse.Namespace) -> None:
    """One warning line on stderr when ``--workers`` asks for more processes than cores."""
    cores, workers = os.cpu_count() or 1, getattr(args, "workers", None)
    if workers is not None and workers > cores:
        say(args, "warning", f"--workers {workers} is more than the {cores} cores; using {cores}")


class DeprecatedAlias(argparse.Action):
    """An old spelling of an option, kept until :data:`ALIASES_UNTIL`: stores into the new one's dest and warns once.

    Args:
        new: the option that replaces it, named in the warning.
    """

    def __init__(self, option_strings: list[str], dest: str, new: str, **kwargs: object) -> None:
        super().__init__(option_strings, dest, **kwargs)
        self.new = new

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: object,
                 option_string: str | None = None) -> None:  # noqa: D102
        if option_string is None and values is None:  # an optional positional not given: argparse still calls
            setattr(namespace, self.dest, values)
            return
        old = option_string or f"the positional {self.metavar or self.dest}"
        print(f"{parser.prog}: warning: {old} is deprecated and goes in {ALIASES_UNTIL}; use {self.new}",
              file=sys.stderr)
        setattr(namespace, self.dest, values)


def add_domain_rules(parser: argparse.ArgumentParser, help_text: str) -> None:
    """``--domain-rules FILE``: a rule file whose R-classifiers are the world model (``--domain`` is its old spelling).

    ``--domain`` names a PDDL domain file in every other command; here it is a deprecated
    alias that warns in one line.
    """
    parser.add_argument("--domain-rules", dest="domain_rules", type=path_arg, default=None, metavar="FILE",
                        help=help_text)
    parser.add_argument("--domain", dest="domain_rules", type=path_arg, action=DeprecatedAlias,
                        new="--domain-rules FILE", help=argparse.SUPPRESS)


ALIASES_UNTIL = "0.3.0"
"""The release that drops the deprecated spellings (the CHANGELOG lists them)."""
PLANNERS = ("bfs", "rules", "gn1", "gn2")
"""``--planner`` wherever plans are made: BFS (up to 6 blocks), the rules of ``--rules FILE``, or a named baseline."""


def add_planner(parser: argparse.ArgumentParser, blocks: str = "up to 6 blocks") -> None:
    """``--planner bfs|rules|gn1|gn2`` (the same choices in every command that makes plans)."""
    parser.add_argument("--planner", choices=PLANNERS, default=None,
                        help=f"who plans: bfs (breadth-first search, {blocks}), rules (the greedy policy of "
                             "--rules FILE), gn1 or gn2 (the GN1 and GN2 baselines); default: rules with --rules, "
                             "else bfs")


def command_parser(sub: argparse._SubParsersAction, name: str, summary: str, example: str,
                   **kwargs: object) -> argparse.ArgumentParser:
    """A subcommand whose ``--help`` starts with its description and one example."""
    text = summary[0].upper() + summary[1:]
    description = f"{textwrap.fill(text, 78)}.\n\nexample:\n  {example}"
    return sub.add_parser(name, help=summary, description=description,
                          formatter_class=argparse.RawDescriptionHelpFormatter, **kwargs)


def blocks_help(low: int, high: int, default: object, more: str = "") -> str:
    """``--blocks``' help in every command: the range and the default, stated the same way."""
    return f"number of blocks, {low}..{high} (default {default}{more})"


def path_arg(text: str) -> str:
    """Argparse type of every file or folder argument: any path but the empty one."""
    if not text:
        raise argparse.ArgumentTypeError("empty path; give a file name")
    return text


def rules_arg(text: str) -> str:
    """Argparse type of every ``--rules``: a rule file's path, or ``builtin`` for the shipped lifted rules."""
    from csql_sim.infra.assets import BUILTIN_RULES, builtin_rules_path

    if text == BUILTIN_RULES:
        return os.fspath(builtin_rules_path())
    return path_arg(text)


RULES_BUILTIN_HELP = "; 'builtin': the shipped lifted rules (any number of blocks)"
"""What every ``--rules`` help ends with."""


def add_overwrite(parser: argparse.ArgumentParser) -> None:
    """``--overwrite``: replace existing output files (added once per parser).

    Without it a command refuses any existing file at an output path; with it, any but a
    model in place of a report (:mod:`csql_sim.infra.outputs`).
    """
    if "--overwrite" in parser._option_string_actions:
        return
    parser.add_argument("--overwrite", action="store_true",
                        help="replace existing output files (default: refuse any existing file; a model is never "
                             "replaced by a report)")


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


def refuse_ignored(args: argparse.Namespace) -> None:
    """One rule for every command: an option the other options make meaningless is refused, not ignored.

    A command declares ``set_defaults(ignored=f)``, ``f(args)`` giving ``{dest: what it needs}``
    for the options that do nothing in this run; such an option must default to None, and any
    that was given is one CsqlError (exit 2) naming it and what it goes with.
    """
    ignored = getattr(args, "ignored", None)
    if ignored is None:
        return
    for dest, needs in ignored(args).items():
        if getattr(args, dest, None) is not None:
            raise CsqlError(f"--{dest.replace('_', '-')} does nothing here: it goes with {needs}")

