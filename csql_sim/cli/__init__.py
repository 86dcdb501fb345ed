"""The ``csql-sim`` command line: a thin layer over the library.

Each subcommand lives in a small module with a ``register(subparsers)`` function; the
handlers call library functions and raise :class:`csql_sim.infra.errors.CsqlError` for bad
input, which :func:`main` prints as one line before exiting with status 2.
"""

from __future__ import annotations

import argparse
import os
import sys

from csql_sim import __version__
from csql_sim.cli import core, demo, discover, learn, pddl_cmd, sim
from csql_sim.cli.output import check_json_output
from csql_sim.infra.errors import CsqlError

SUBCOMMAND_MODULES = (core, learn, sim, demo, discover, pddl_cmd)


class OneLineParser(argparse.ArgumentParser):
    """An ArgumentParser whose usage errors are one line on stderr and exit status 2."""

    def error(self, message: str) -> None:  # noqa: D102
        one_line = " ".join(message.split())
        self.exit(2, f"{self.prog}: error: {one_line} (see --help)\n")


def build_parser() -> argparse.ArgumentParser:
    """The full parser with every subcommand registered."""
    parser = OneLineParser(
        prog="csql-sim",
        description="Classifier-system Q-learning on the blocks world, executed on a simulated arm.",
    )
    parser.add_argument("--version", action="version", version=f"csql-sim {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=OneLineParser)
    for module in SUBCOMMAND_MODULES:
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the console script; returns the exit status."""
    args = build_parser().parse_args(argv)
    try:
        check_json_output(args)
        return int(args.func(args) or 0)
    except CsqlError as exc:
        print(f"csql-sim: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # The reader (e.g. `| head`) closed the pipe: stop quietly, as Unix tools do.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except KeyboardInterrupt:
        _close_progress_bars()
        print("csql-sim: interrupted", file=sys.stderr)
        return 130


def _close_progress_bars() -> None:
    """End every open progress bar's line, so that a message after it starts a line of its own."""
    tqdm = sys.modules.get("tqdm")
    if tqdm is None:
        return
    for bar in list(getattr(tqdm.tqdm, "_instances", ())):
        bar.close()


if __name__ == "__main__":
    sys.exit(main())
