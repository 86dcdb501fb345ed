"""The README's library example runs, and the docs use the library, not the CLI's modules."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _pages():
    """Every Markdown page of the site, the guide's and the results' (``docs/results/``) alike."""
    return sorted((ROOT / "docs").rglob("*.md"))


def test_readme_library_example_runs(tmp_path, monkeypatch, capsys):
    text = (ROOT / "README.md").read_text()
    section = text[text.index("### As a library"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README.md", "exec"), {})
    out = capsys.readouterr().out.splitlines()
    assert (tmp_path / "pruned.yaml").exists()
    assert out[-1] == "True 8 8"  # the arm reached the goal with the optimal 8 actions
    assert out[-2].startswith("['unstack(A,B)'") and out[-2].count("'") == 16


def test_docs_do_not_import_the_cli():
    for doc in [ROOT / "README.md", *_pages()]:
        assert "csql_sim.cli" not in doc.read_text(), doc.name


def _commands():
    """Each subcommand's parser, by name (from the CLI's own argparse parser)."""
    import argparse

    from csql_sim.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices


def _code(text):
    """The code in a Markdown text: fenced blocks and inline spans."""
    blocks = re.findall(r"```[a-z]*\n(.*?)```", text, re.S)
    rest = re.sub(r"```[a-z]*\n.*?```", "", text, flags=re.S)
    return [*blocks, *re.findall(r"`([^`\n]+)`", rest)]


def _invocations(text):
    """``(command, [--options])`` for every ``csql-sim COMMAND ...`` written in the code of a Markdown text."""
    found = []
    for code in _code(text):
        code = code.replace("\\\n", " ")
        for match in re.finditer(r"(?<![\"'\w])csql-sim ([a-z][a-z-]*)([^\n|;#>&]*)", code):
            found.append((match.group(1), re.findall(r"(?<![\w-])(--[a-z][a-z0-9-]*)", match.group(2))))
    return found


def test_every_command_and_option_the_docs_name_exists():
    """README.md and docs/*.md name only commands and options that ``--help`` has (issue 28)."""
    from csql_sim.cli.args import DeprecatedAlias

    commands = _commands()
    wrong = []
    for doc in [ROOT / "README.md", *_pages()]:
        for command, options in _invocations(doc.read_text()):
            if command not in commands:
                wrong.append(f"{doc.name}: csql-sim {command}")
                continue
            known = commands[command]._option_string_actions
            wrong += [f"{doc.name}: csql-sim {command} {o}" for o in options if o not in known]
            wrong += [f"{doc.name}: csql-sim {command} {o} (deprecated)" for o in options
                      if isinstance(known.get(o), DeprecatedAlias)]
        for command, word in re.findall(r"csql-sim (show|prune) ([^-\s`][^\s`]*)", doc.read_text()):
            wrong.append(f"{doc.name}: csql-sim {command} {word} (the positional rule file is deprecated)")
    assert wrong == []


def test_the_readme_names_every_command():
    text = (ROOT / "README.md").read_text()
    named = {command for command, _ in _invocations(text)} | set(_code(text))
    assert set(_commands()) - named == set()


def test_the_readme_is_short():
    """Issue 31: the README says what the tool is and how to start; the rest is in the site."""
    assert len((ROOT / "README.md").read_text().splitlines()) <= 250


def test_every_page_of_docs_is_in_the_site_navigation():
    import yaml

    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text())

    def pages(nav):
        for item in nav:
            value = next(iter(item.values())) if isinstance(item, dict) else item
            yield from (pages(value) if isinstance(value, list) else [value])

    listed = list(pages(config["nav"]))
    assert sorted(listed) == sorted(p.relative_to(ROOT / "docs").as_posix() for p in _pages())
