"""MkDocs hooks: pages generated from their one source, so that none can drift.

* ``docs/commands.md``'s marker ``<!-- csql-sim commands -->`` becomes every subcommand's
  ``--help``, from the command line's own argparse parser;
* ``<!-- json-commands -->`` becomes the list of commands that take ``--json``;
* ``docs/index.md``'s marker ``<!-- readme -->`` becomes ``README.md``, its links into
  ``docs/`` made relative to the site.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

MARKER = "<!-- csql-sim commands -->"
JSON_MARKER = "<!-- json-commands -->"
README_MARKER = "<!-- readme -->"
ROOT = Path(__file__).resolve().parents[1]


def _subcommands() -> dict[str, argparse.ArgumentParser]:
    os.environ["COLUMNS"] = "100"  # argparse wraps help to the terminal's width
    from csql_sim.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {"": parser, **sub.choices}


def json_commands() -> str:
    """The commands that take ``--json``, as a Markdown list of code spans."""
    names = [f"`{name}`" for name, p in _subcommands().items() if name and "--json" in p._option_string_actions]
    return ", ".join(names[:-1]) + " and " + names[-1]


def command_reference() -> str:
    """Markdown: one section per subcommand with its full ``--help``, in the order of ``csql-sim --help``."""
    commands = _subcommands()
    parts = ["```text", commands.pop("").format_help().rstrip(), "```"]
    for name, command in commands.items():
        parts += ["", f"## {name}", "", "```text", command.format_help().rstrip(), "```"]
    return "\n".join(parts) + "\n"


def on_page_markdown(markdown: str, page, config, files) -> str:  # noqa: ANN001 (MkDocs' hook signature)
    """Replace the markers by the generated command reference and the list of commands that take ``--json``."""
    if MARKER in markdown:
        markdown = markdown.replace(MARKER, command_reference())
    if README_MARKER in markdown:
        markdown = markdown.replace(README_MARKER, (ROOT / "README.md").read_text().replace("](docs/", "]("))
    return markdown.replace(JSON_MARKER, json_commands()) if JSON_MARKER in markdown else markdown
