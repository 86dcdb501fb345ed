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


__all__ = ["asset_text"]
