"""The import graph of csql_sim: its cycles, and the layer picture of docs/architecture.md.

Every ``import`` and ``from ... import`` statement of every module counts, wherever it
stands (in a function, under ``if TYPE_CHECKING``); relative imports are resolved, and
``from package import module`` counts as an import of the module. A package's
``__init__`` importing its own subpackages and modules, or a module importing one of the
packages it lives in, is not an edge.

    python scripts/architecture.py           # print the generated section
    python scripts/architecture.py --write   # rewrite it in docs/architecture.md
    python scripts/architecture.py --check   # exit 1 (one line) if out of date or cyclic
"""

from __future__ import annotations

import argparse
import ast
import re
import sys
from collections import Counter, deque
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE_DIR = ROOT / "csql_sim"
PYPROJECT = ROOT / "pyproject.toml"
DOC = ROOT / "docs" / "architecture.md"
BEGIN = "<!-- generated:begin -->"
END = "<!-- generated:end -->"

Graph = dict[str, set[str]]


# ------------------------------------------------------------------ the graph
def module_files(package_dir: Path) -> dict[str, Path]:
    """Every module under ``package_dir`` by dotted name; a package's ``__init__`` has the package's name."""
    modules = {}
    for path in sorted(package_dir.rglob("*.py")):
        parts = path.relative_to(package_dir.parent).with_suffix("").parts
        if "__pycache__" in parts:
            continue
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        modules[name] = path
    return modules


def from_base(node: ast.ImportFrom, here: str) -> str:
    """The absolute package or module a ``from ... import`` reads from; ``here`` is the importer's package."""
    if not node.level:
        return node.module or ""
    parts = here.split(".")
    base = ".".join(parts[: len(parts) - node.level + 1])
    return f"{base}.{node.module}" if node.module else base


def import_targets(tree: ast.AST, module: str, is_package: bool, modules: dict[str, Path]) -> set[str]:
    """The modules of ``modules`` that the statements of ``tree`` import (``from a import b``: a.b if a module)."""
    here = module if is_package else module.rpartition(".")[0]
    targets: set[str | None] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets.update(owning_module(alias.name, modules) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = from_base(node, here)
            for alias in node.names:
                full = f"{base}.{alias.name}"
                targets.add(full if full in modules else owning_module(base, modules))
    return {t for t in targets if t is not None}


def owning_module(name: str, modules: dict[str, Path]) -> str | None:
    """The longest prefix of ``name`` that is one of ``modules`` (None for other packages)."""
    parts = name.split(".")
    for end in range(len(parts), 0, -1):
        prefix = ".".join(parts[:end])
        if prefix in modules:
            return prefix
    return None


def is_related(a: str, b: str) -> bool:
    """Whether one of the two names is a package the other lives in."""
    return a.startswith(b + ".") or b.startswith(a + ".")


def read_graph(package_dir: Path = PACKAGE_DIR) -> Graph:
    """Module -> the package's modules it imports (see the module docstring for what counts)."""
    modules = module_files(package_dir)
    graph: Graph = {}
    for module, path in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        targets = import_targets(tree, module, path.name == "__init__.py", modules)
        graph[module] = {t for t in targets if t and t != module and not is_related(module, t)}
    return graph


# ------------------------------------------------------------------ cycles
def find_cycles(graph: Graph) -> list[list[str]]:
    """The import cycles: strongly connected components of more than one module, sorted (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for target in sorted(graph.get(node, ())):
            if target not in index:
                visit(target)
                low[node] = min(low[node], low[target])
            elif target in on_stack:
                low[node] = min(low[node], index[target])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                components.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return sorted(components)


def shortest_cycle(graph: Graph, component: list[str]) -> list[str]:
    """One shortest cycle through the first module of a component, as a path that ends where it starts."""
    first = component[0]
    parent: dict[str, str] = {}
    queue = deque([first])
    while queue:
        node = queue.popleft()
        for target in sorted(graph.get(node, ())):
            if target == first:
                path = [node]
                while path[-1] != first:
                    path.append(parent[path[-1]])
                return [first, *reversed(path[:-1]), first]
            if target in component and target not in parent:
                parent[target] = node
                queue.append(target)
    return component


def describe_cycles(graph: Graph, cycles: list[list[str]]) -> str:
    """The cycles in one line: each as one shortest loop, with the size of its component."""
    loops = []
    for component in cycles:
        loop = " -> ".join(short(m) for m in shortest_cycle(graph, component))
        loops.append(f"{loop} ({len(component)} modules in the cycle)")
    return "; ".join(loops)


# ------------------------------------------------------------------ the picture
def short(module: str) -> str:
    """A module's name without the package: ``core.world``; the root package's ``__init__`` is ``__init__``."""
    return module.partition(".")[2] or "__init__"


def folder_of(module: str) -> str:
    """The layer folder of a module (``core``), or the root module's own name (``__main__``)."""
    rest = short(module)
    return rest.split(".")[0]


def layer_order(pyproject: Path = PYPROJECT) -> list[list[str]]:
    """The layers of the import-linter layers contract, top first; each a list of folder names."""
    text = pyproject.read_text(encoding="utf-8")
    try:
        import tomllib
    except ImportError:  # Python 3.10: the one list, read with a regex
        block = re.search(r'type\s*=\s*"layers"\s*\nlayers\s*=\s*\[(.*?)\]', text, re.S)
        layers = re.findall(r'"([^"]+)"', block.group(1)) if block else []
    else:
        contracts = tomllib.loads(text)["tool"]["importlinter"]["contracts"]
        layers = next(c["layers"] for c in contracts if c["type"] == "layers")
    return [[part.strip().rpartition(".")[2] for part in layer.split("|")] for layer in layers]


def folder_order(folders: set[str], layers: list[list[str]]) -> list[str]:
    """Root modules first, then the layers top to bottom, then any folder the contract does not name."""
    in_layers = [f for layer in layers for f in layer]
    roots = sorted(f for f in folders if f.startswith("__"))
    others = sorted(f for f in folders if f not in in_layers and f not in roots)
    return roots + [f for f in in_layers if f in folders] + others


def node_id(folder: str) -> str:
    """A Mermaid node id for a folder (``__main__`` -> ``root_main``)."""
    return f"root_{folder.strip('_')}" if folder.startswith("__") else folder


def node_label(folder: str) -> str:
    """What a node shows: ``core/`` for a folder, ``__main__.py`` for a root module."""
    return f"{folder}.py" if folder.startswith("__") else f"{folder}/"


def mermaid(graph: Graph, order: list[str]) -> list[str]:
    """A ``flowchart TD``: one node per folder, edges labelled with module-to-module import counts."""
    counts = Counter((folder_of(m), folder_of(t)) for m, targets in graph.items() for t in targets)
    rank = {f: k for k, f in enumerate(order)}
    lines = ["```mermaid", "flowchart TD"]
    lines += [f'    {node_id(f)}["{node_label(f)}"]' for f in order]
    for (a, b), count in sorted(counts.items(), key=lambda item: (rank[item[0][0]], rank[item[0][1]])):
        if a != b:
            lines.append(f"    {node_id(a)} -->|{count}| {node_id(b)}")
    lines.append("```")
    return lines


def module_table(modules: dict[str, Path], order: list[str]) -> list[str]:
    """A plain-text table: each folder's modules and their line counts, with the folder's total."""
    rows = []
    for folder in order:
        members = sorted((m, p) for m, p in modules.items() if folder_of(m) == folder)
        sizes = [(p.name, len(p.read_text(encoding="utf-8").splitlines())) for _, p in members]
        if folder.startswith("__"):
            rows.append(("(root)", sizes[0][0], sizes[0][1]))
            continue
        rows.append((f"{folder}/", f"({len(sizes)} modules)", sum(n for _, n in sizes)))
        rows += [("", name, n) for name, n in sorted(sizes)]
    width = max(len(name) for _, name, _ in rows)
    lines = ["```text", f"{'folder':<12}{'module':<{width}}  {'lines':>5}"]
    lines += [f"{folder:<12}{name:<{width}}  {n:>5}" for folder, name, n in rows]
    return [*lines, "```"]


def generated_section(graph: Graph | None = None, package_dir: Path = PACKAGE_DIR,
                      pyproject: Path = PYPROJECT) -> str:
    """The text between the markers: the Mermaid picture, then the module table."""
    graph = read_graph(package_dir) if graph is None else graph
    order = folder_order({folder_of(m) for m in graph}, layer_order(pyproject))
    intro = [f"Generated by `python scripts/architecture.py --write` from the imports of {len(graph)} modules; "
             "an edge's number counts module-to-module imports between the two folders."]
    return "\n".join([*intro, "", *mermaid(graph, order), "", *module_table(module_files(package_dir), order)])


# ------------------------------------------------------------------ the document
def split_doc(text: str) -> tuple[str, str, str]:
    """The document before, between and after the markers (ValueError if they are missing)."""
    if BEGIN not in text or END not in text:
        raise ValueError(f"the markers {BEGIN} and {END} are missing")
    head, _, rest = text.partition(BEGIN)
    body, _, tail = rest.partition(END)
    return head, body, tail


def updated_doc(text: str, section: str) -> str:
    """The document with ``section`` between the markers."""
    head, _, tail = split_doc(text)
    return f"{head}{BEGIN}\n{section}\n{END}{tail}"


def shown(path: Path) -> str:
    """A path as the messages show it: relative to the repository when inside it."""
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


def check(doc: Path = DOC, graph: Graph | None = None) -> str | None:
    """None if the document is up to date and there is no cycle, otherwise one line saying what is wrong."""
    problems = []
    graph = read_graph() if graph is None else graph
    cycles = find_cycles(graph)
    if cycles:
        problems.append(f"import cycles: {describe_cycles(graph, cycles)}")
    text = doc.read_text(encoding="utf-8") if doc.exists() else ""
    try:
        current = updated_doc(text, generated_section(graph)) == text
    except ValueError as exc:
        problems.append(f"{shown(doc)}: {exc}")
    else:
        if not current:
            problems.append(f"{shown(doc)} is out of date: run python scripts/architecture.py --write")
    return "; ".join(problems) or None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--write", action="store_true", help="rewrite the generated section of docs/architecture.md")
    mode.add_argument("--check", action="store_true", help="exit 1 if that section is out of date or a cycle exists")
    args = parser.parse_args(argv)
    if args.check:
        problem = check()
        print(f"architecture: {problem or 'docs/architecture.md is up to date; no import cycles'}")
        return 1 if problem else 0
    if args.write:
        graph = read_graph()
        DOC.write_text(updated_doc(DOC.read_text(encoding="utf-8"), generated_section(graph)), encoding="utf-8")
        print(f"architecture: wrote {shown(DOC)}")
        if cycles := find_cycles(graph):
            print(f"architecture: import cycles: {describe_cycles(graph, cycles)}", file=sys.stderr)
        return 0
    print(generated_section())
    return 0


if __name__ == "__main__":
    sys.exit(main())
