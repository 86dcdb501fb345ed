"""The legend of the arm's cubes: which object is which colour.

Every physical command (``execute``, ``render``, ``evaluate``, ``demo``) shows it: the
object's name (the cube letter for a task in the notation, the PDDL object name for a
PDDL task) and its cube's colour word (:data:`~csql_sim.sim.world.config.COLOUR_NAMES`). Videos
draw it in the top left of every frame, with the colour words in the frames before the
first action (:func:`draw_legend`); text reports print :func:`legend_line`; JSON reports
carry :func:`cube_legend` as their ``"legend"`` field.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from csql_sim.core.state.world import LETTERS
from csql_sim.sim.world.config import COLOUR_NAMES, COLOURS

if TYPE_CHECKING:
    from PIL import ImageDraw


def legend_names(n: int, names: Sequence[str] | None = None) -> tuple[str, ...]:
    """The names of cubes 0..n-1: ``names`` as given, or the cube letters A, B, ..."""
    if names is None:
        return tuple(LETTERS[:n])
    if len(names) != n:
        raise ValueError(f"{len(names)} names for {n} cubes")
    return tuple(names)


def cube_legend(n: int, names: Sequence[str] | None = None) -> dict[str, str]:
    """Object name -> cube colour (``{"a": "red", "b": "green"}``), in cube order (JSON's ``legend``)."""
    return {name: COLOUR_NAMES[i] for i, name in enumerate(legend_names(n, names))}


def legend_line(n: int, names: Sequence[str] | None = None) -> str:
    """``legend: a = red, b = green, ...``: the text reports' line."""
    return "legend: " + ", ".join(f"{name} = {colour}" for name, colour in cube_legend(n, names).items())


def draw_legend(draw: ImageDraw.ImageDraw, width: int, size: float, names: Sequence[str], full: bool) -> None:
    """Draw a coloured square and the name of each cube along the top, wrapping lines as needed.

    Args:
        draw: the frame's drawing context.
        width: the frame's width in pixels.
        size: the squares' side in pixels (the text is about as tall).
        names: the cubes' names, in cube order.
        full: add each cube's colour word (``ruby = magenta``), as the first frames do.

    A name other than the cube's letter is followed by the letter, which the captions'
    actions and states use: ``ruby (F)``.
    """
    from PIL import ImageFont

    font = ImageFont.load_default(size=max(8, int(size * 0.8)))
    x, y, gap = 4.0, 4.0, max(3.0, size / 3)
    for i, name in enumerate(names):
        label = name if name == LETTERS[i] else f"{name} ({LETTERS[i]})"
        label = f"{label} = {COLOUR_NAMES[i]}" if full else label
        span = size + gap / 2 + draw.textlength(label, font=font) + gap
        if x > 4 and x + span > width - 4:
            x, y = 4.0, y + size + gap
        colour = tuple(int(255 * c) for c in COLOURS[i][:3])
        draw.rectangle((x, y, x + size, y + size), fill=colour, outline=(255, 255, 255))
        draw.text((x + size + gap / 2, y + size / 2), label, fill=(255, 255, 255), font=font, anchor="lm",
                  stroke_width=1, stroke_fill=(0, 0, 0))
        x += span


__all__ = ["cube_legend", "draw_legend", "legend_line", "legend_names"]
