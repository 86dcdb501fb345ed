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


def test_no_page_cites_an_issue_number():
    """The docs say things in plain words: no "issue 33", no "the issue's targets"."""
    cites = re.compile(r"\bissues?\s*#?\d+|\bthe issue's\b|\bof the issue\b", re.I)
    wrong = [f"{doc.relative_to(ROOT)}: {m.group(0)}" for doc in [ROOT / "README.md", *_pages()]
             for m in cites.finditer(doc.read_text())]
    assert wrong == []


def _provenance(text):
    """The rows of a results page's table of its tables: ``(table, measured, command, tasks)``."""
    header = "| table | measured | regenerate with | tasks |\n|---|---|---|---|\n"
    assert header in text
    rows = text.split(header, 1)[1].split("\n\n", 1)[0].splitlines()
    return [[cell.strip() for cell in row.strip("|").split(" | ")] for row in rows]


def test_every_results_table_is_dated_with_its_command_and_tasks():
    """Each results page opens with its tables: the day measured, the command, tuning or held-out tasks."""
    pages = sorted((ROOT / "docs" / "results").glob("*.md"))
    assert {p.name for p in pages} >= {"index.md", "lifted.md", "features.md"}
    for page in pages:
        if page.name == "index.md":
            continue
        rows = _provenance(page.read_text())
        assert rows, page.name
        for table, measured, command, tasks in rows:
            assert re.fullmatch(r"\[[^]]+\]\(#[a-z0-9-]+\)( \(.*\))?", table), (page.name, table)
            assert re.search(r"\b2\d{3}-\d{2}-\d{2}\b", measured), (page.name, table)
            assert "`csql-sim " in command or "`python benchmarks/" in command or command.startswith("the same"), \
                (page.name, table)
            assert re.search(r"tuning|held-out|every (pair|transition)|test task|timing", tasks), (page.name, table)
    held_out = _provenance((ROOT / "docs" / "results" / "lifted.md").read_text())
    assert any("held-out" in tasks for *_, tasks in held_out)


def test_the_benchmarks_the_docs_name_exist_and_name_pages_that_exist():
    """Every ``benchmarks/NAME.py`` a page names is there, and each script's docstring names a page that is."""
    for doc in [ROOT / "README.md", *_pages()]:
        for script in re.findall(r"\bbenchmarks/([a-z0-9_]+\.py)", doc.read_text()):
            assert (ROOT / "benchmarks" / script).is_file(), f"{doc.name}: benchmarks/{script}"
    for script in sorted((ROOT / "benchmarks").glob("*.py")):
        doc = script.read_text().split('"""')[1]
        named = re.findall(r"Regenerates ((?:docs/[a-z0-9_/]+\.md(?:,| and |\s)+)+)", " ".join(doc.split()))
        assert named, script.name
        for page in re.findall(r"docs/[a-z0-9_/]+\.md", named[0]):
            assert (ROOT / page).is_file(), f"{script.name}: {page}"
