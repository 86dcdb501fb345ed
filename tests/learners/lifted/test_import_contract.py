"""The generated path imports no hand-written concept: the import contract, checked on the source itself.

The import closure of each module the contract names is computed here from the source (every
``import`` statement, those inside functions too), independently of import-linter; the modules
that define the hand concepts are found by the names they define, not listed by hand.
"""

import ast
import importlib.util
from pathlib import Path

import pytest

import csql_sim

ROOT = Path(csql_sim.__file__).parent
CONTRACT = "The generated-feature learner, its features and its policy import no hand-written concept"
HAND_CONCEPTS = ("well_placed", "deadlocked", "deadlock_cover", "target_goal", "MoveRelations", "hand_ordering")
"""Names whose definitions are hand-written concepts of the task: misplaced/well placed, deadlock, cover,
the goal without its held block, the given atoms' relations, the hand ordering."""


def contract() -> dict:
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+
    doc = tomllib.loads((Path(__file__).resolve().parents[3] / "pyproject.toml").read_text())  # the checkout's
    return next(c for c in doc["tool"]["importlinter"]["contracts"] if c["name"] == CONTRACT)


def modules_in(name: str) -> list[str]:
    """The module, or every module of the package, by dotted name."""
    spec = importlib.util.find_spec(name)
    path = Path(spec.origin)
    if path.name != "__init__.py":
        return [name]
    return [".".join(p.relative_to(ROOT.parent).with_suffix("").parts).removesuffix(".__init__")
            for p in sorted(path.parent.rglob("*.py"))]


def imports_of(name: str) -> set[str]:
    """The csql_sim modules a module's source imports (the module itself for ``from pkg import module``)."""
    tree = ast.parse(Path(importlib.util.find_spec(name).origin).read_text())
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.add(node.module)
            out |= {f"{node.module}.{a.name}" for a in node.names
                    if importlib.util.find_spec(node.module).submodule_search_locations is not None
                    and importlib.util.find_spec(f"{node.module}.{a.name}") is not None}
    return {m for m in out if m.startswith("csql_sim.")}


def closure(names: list[str]) -> set[str]:
    seen, todo = set(), list(names)
    while todo:
        name = todo.pop()
        if name not in seen:
            seen.add(name)
            todo.extend(imports_of(name) - seen)
    return seen


def defining(names: tuple[str, ...]) -> set[str]:
    """The modules of csql_sim that define a function or class of one of these names."""
    out = set()
    for path in ROOT.rglob("*.py"):
        tree = ast.parse(path.read_text())
        if any(isinstance(n, (ast.FunctionDef, ast.ClassDef)) and n.name in names for n in tree.body):
            out.add(".".join(path.relative_to(ROOT.parent).with_suffix("").parts))
    return out


def test_the_generated_path_imports_no_module_that_defines_a_hand_concept():
    c = contract()
    sources = [m for s in c["source_modules"] for m in modules_in(s)]
    hand = defining(HAND_CONCEPTS)
    assert {"csql_sim.core.state.goal_relations", "csql_sim.core.state.move_relations"} <= hand
    assert hand <= set(c["forbidden_modules"])  # the contract forbids every one of them
    reached = closure(sources)
    assert "csql_sim.core.state.moves" in reached and "csql_sim.core.features.grammar" in reached
    assert not reached & set(c["forbidden_modules"]), sorted(reached & set(c["forbidden_modules"]))


@pytest.mark.parametrize("module", ["csql_sim.learners.lifted.ql", "csql_sim.core.policies.lifted_policy"])
def test_the_closure_finds_the_hand_concepts_where_the_given_atoms_use_them(module):
    assert "csql_sim.core.state.goal_relations" in closure([module])  # so the test above can fail
