"""Each subcommand is registered by the module SUBCOMMANDS names, so a command's run builds its own parser alone."""

import argparse
import importlib

from csql_sim.cli import SUBCOMMANDS, OneLineParser, build_parser


def _names(parser: argparse.ArgumentParser) -> list[str]:
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return list(sub.choices)


def test_every_module_registers_exactly_the_commands_named_for_it():
    for name, commands in SUBCOMMANDS.items():
        parser = OneLineParser(prog="csql-sim")
        importlib.import_module(f"csql_sim.cli.{name}").register(parser.add_subparsers())
        assert tuple(_names(parser)) == commands, name


def test_the_full_parser_lists_every_command_and_a_command_gets_its_own_module():
    assert _names(build_parser()) == [c for commands in SUBCOMMANDS.values() for c in commands]
    assert _names(build_parser("plan")) == list(SUBCOMMANDS["core"])
    assert _names(build_parser("no-such-command")) == _names(build_parser())
