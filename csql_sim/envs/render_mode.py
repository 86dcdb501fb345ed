"""Render modes as Gymnasium specifies them: an environment refuses a mode it does not list.

``gymnasium.make`` reads the entry point's ``metadata["render_modes"]`` (the registration's
entry points carry their class's metadata): it turns ``"human"`` into ``"rgb_array"`` with
its ``HumanRendering`` wrapper and ``"rgb_array_list"`` into ``"rgb_array"`` with
``RenderCollection`` where the environment renders images, and warns about any other mode
it does not find there. The environment itself then refuses that mode with Gymnasium's
own exception, :class:`gymnasium.error.UnsupportedMode` (:class:`UnsupportedRenderMode`
is also a :class:`~csql_sim.infra.errors.CsqlError`, the package's one-line error).
"""

from __future__ import annotations

from collections.abc import Sequence

from gymnasium.error import UnsupportedMode

from csql_sim.infra.errors import CsqlError


class UnsupportedRenderMode(CsqlError, UnsupportedMode):
    """A render mode the environment does not list in ``metadata["render_modes"]``."""


def check_render_mode(render_mode: object, modes: Sequence[str]) -> None:
    """Nothing if ``render_mode`` is None or one of ``modes``; else :class:`UnsupportedRenderMode`."""
    if render_mode is not None and render_mode not in modes:
        raise UnsupportedRenderMode(f"render_mode must be one of {', '.join(map(repr, modes))} or None, "
                                    f"got {render_mode!r}")


__all__ = ["UnsupportedRenderMode", "check_render_mode"]
