"""The README's library example runs, and the docs use the library, not the CLI's modules."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


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
    for doc in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        assert "csql_sim.cli" not in doc.read_text(), doc.name
