"""The files that ship with csql-sim (``assets/``, installed as the package ``csql_sim.assets``)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path


def asset_text(folder: str, name: str) -> str:
    """An asset's text: the installed ``csql_sim.assets``, else the checkout's ``assets/``.

    The second case is a source checkout that shadows the installed package (``python -m``
    run inside it puts the checkout first on ``sys.path``), where ``csql_sim.assets`` exists
    only as the top-level folder.
    """
    try:
        return resources.files("csql_sim.assets").joinpath(folder, name).read_text(encoding="utf-8")
    except ModuleNotFoundError:
        return (Path(__file__).resolve().parents[2] / "assets" / folder / name).read_text(encoding="utf-8")


BUILTIN_RULES = "builtin"
"""The name of the shipped lifted rules wherever ``--rules`` is taken (``--rules builtin``)."""
BUILTIN_RULES_FILE = ("rules", "lifted.json")
"""The shipped lifted rules, under ``assets/`` (installed as ``csql_sim.assets``)."""


def asset_path(folder: str, name: str) -> Path:
    """An asset's path on disk: the installed ``csql_sim.assets``, else the checkout's ``assets/``."""
    try:
        found = Path(str(resources.files("csql_sim.assets").joinpath(folder, name)))
    except ModuleNotFoundError:
        found = None
    if found is None or not found.is_file():
        found = Path(__file__).resolve().parents[2] / "assets" / folder / name
    return found


def builtin_rules_path() -> Path:
    """The file that ``--rules builtin`` names: the shipped lifted rules (any number of blocks)."""
    return asset_path(*BUILTIN_RULES_FILE)


__all__ = ["BUILTIN_RULES", "asset_path", "asset_text", "builtin_rules_path"]
