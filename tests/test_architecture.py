"""The import graph: no cycles, the layers contract holds, docs/architecture.md's picture is current."""

import importlib.util
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "scripts" / "architecture.py"

if not SCRIPT.exists():
    pytest.skip("scripts/architecture.py is not here (tests run outside the repository?)", allow_module_level=True)


def _load_script():
    spec = importlib.util.spec_from_file_location("architecture_script", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


architecture = _load_script()


@pytest.fixture(scope="module")
def graph():
    """The package's import graph, read once (half a second)."""
    return architecture.read_graph()


def _write(root: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text))


def test_find_cycles_on_a_graph():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a", "e"}, "e": set(), "f": {"f"}}
    assert architecture.find_cycles(graph) == [["a", "b", "c"]]
    assert architecture.find_cycles({"a": {"b"}, "b": set()}) == []


def test_a_cycle_made_by_an_import_inside_a_function(tmp_path):
    _write(tmp_path, {
        "pkg/__init__.py": "from pkg import a\nfrom . import sub\n",  # a package importing its children: no edge
        "pkg/a.py": "from . import b\nimport numpy\n",
        "pkg/b.py": "def f():\n    from pkg.a import x\n    return x\n",  # the cycle's only way back
        "pkg/c.py": "import pkg\nfrom pkg import sub\nfrom .sub.d import y\n",  # pkg itself: no edge
        "pkg/sub/__init__.py": "",
        "pkg/sub/d.py": "from .. import c as _c\nfrom ..a import *\n",
    })
    graph = architecture.read_graph(tmp_path / "pkg")
    assert graph == {
        "pkg": set(),
        "pkg.a": {"pkg.b"},
        "pkg.b": {"pkg.a"},
        "pkg.c": {"pkg.sub", "pkg.sub.d"},
        "pkg.sub": set(),
        "pkg.sub.d": {"pkg.c", "pkg.a"},
    }
    assert architecture.find_cycles(graph) == [["pkg.a", "pkg.b"], ["pkg.c", "pkg.sub.d"]]
    graph["pkg.b"] = set()  # without the import in the function
    assert architecture.find_cycles(graph) == [["pkg.c", "pkg.sub.d"]]


def test_no_import_cycle_in_the_package(graph):
    cycles = architecture.find_cycles(graph)
    assert not cycles, architecture.describe_cycles(graph, cycles)


def test_the_layers_come_from_pyproject():
    layers = architecture.layer_order()
    assert layers[0] == ["cli", "testing", "up_engine"] and layers[1] == ["api"] and layers[-1] == ["infra"]
    assert ["discovery", "learners"] in layers


def test_docs_picture_is_current(graph):
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    _, body, _ = architecture.split_doc(text)
    assert body.strip("\n") == architecture.generated_section(graph), "run: python scripts/architecture.py --write"


def test_lint_imports_contracts_hold():
    pytest.importorskip("importlinter", reason="import-linter is not installed (pip install -e '.[test]')")
    run = "import sys; from importlinter.cli import lint_imports_command; sys.exit(lint_imports_command())"
    done = subprocess.run([sys.executable, "-c", run, "--no-cache", "--no-logo"], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr


def test_check_finds_a_stale_section(tmp_path, graph):
    doc = tmp_path / "architecture.md"
    doc.write_text(f"# title\n{architecture.BEGIN}\nold picture\n{architecture.END}\nprose\n")
    assert "is out of date" in architecture.check(doc, graph)
    doc.write_text(architecture.updated_doc(doc.read_text(), architecture.generated_section(graph)))
    assert doc.read_text().endswith(f"{architecture.END}\nprose\n")
    assert "out of date" not in (architecture.check(doc, graph) or "")
    doc.write_text("no markers\n")
    assert "markers" in architecture.check(doc, graph)
