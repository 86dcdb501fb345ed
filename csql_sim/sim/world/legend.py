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
from functools import cache, lru_cache
from typing import TYPE_CHECKING

from csql_sim.core.state.state import default_name, default_names
from csql_sim.sim.world.config import colour_name, cube_colour

if TYPE_CHECKING:
    import numpy as np
    from PIL import Image, ImageDraw, ImageFont


def legend_names(n: int, names: Sequence[str] | None = None) -> tuple[str, ...]:
    """The names of cubes 0..n-1: ``names`` as given, or the cube letters A, B, ..."""
    if names is None:
        return default_names(n)
    if len(names) != n:
        raise ValueError(f"{len(names)} names for {n} cubes")
    return tuple(names)


def cube_legend(n: int, names: Sequence[str] | None = None) -> dict[str, str]:
    """Object name -> cube colour (``{"a": "red", "b": "green"}``), in cube order (JSON's ``legend``)."""
    return {name: colour_name(i) for i, name in enumerate(legend_names(n, names))}


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
        label = name if name == default_name(i) else f"{name} ({default_name(i)})"
        label = f"{label} = {colour_name(i)}" if full else label
        span = size + gap / 2 + draw.textlength(label, font=font) + gap
        if x > 4 and x + span > width - 4:
            x, y = 4.0, y + size + gap
        colour = tuple(int(255 * c) for c in cube_colour(i)[:3])
        draw.rectangle((x, y, x + size, y + size), fill=colour, outline=(255, 255, 255))
        draw.text((x + size + gap / 2, y + size / 2), label, fill=(255, 255, 255), font=font, anchor="lm",
                  stroke_width=1, stroke_fill=(0, 0, 0))
        x += span


def draw_labels(img: Image.Image, xy: np.ndarray, depth: np.ndarray, names: Sequence[str],
                pixels: np.ndarray) -> None:
    """Write each cube's name on the cube, at its projected centre ``xy[i]`` (white on a dark outline).

    Args:
        img: the frame.
        xy: the cubes' centres in pixels (n, 2).
        depth: their depths along the view axis (n,); a cube at depth <= 0 is not labelled.
        names: the cubes' names, in cube order.
        pixels: each cube's edge on the screen in pixels (n,): the text is about half that tall.

    Far cubes are labelled first, so a near cube's name is written over a far one's.
    """
    for i in sorted(range(len(names)), key=lambda k: (-float(depth[k]), k)):
        if depth[i] <= 0:
            continue
        sprite = _label(names[i], int(min(16, max(10, pixels[i] * 0.5))))
        img.paste(sprite, (int(round(xy[i][0])) - sprite.width // 2, int(round(xy[i][1])) - sprite.height // 2),
                  sprite)


@lru_cache(maxsize=1024)
def _label(name: str, size: int) -> Image.Image:
    """The name in white on a dark outline, on a transparent ground just large enough."""
    from PIL import Image, ImageDraw

    font = _font(size)
    left, top, right, bottom = font.getbbox(name, stroke_width=2)
    img = Image.new("RGBA", (right - left + 2, bottom - top + 2), (0, 0, 0, 0))
    ImageDraw.Draw(img).text((1 - left, 1 - top), name, fill=(255, 255, 255, 255), font=font, stroke_width=2,
                             stroke_fill=(0, 0, 0, 255))
    return img


@cache
def _font(size: int) -> ImageFont.FreeTypeFont:
    from PIL import ImageFont

    return ImageFont.load_default(size=size)


__all__ = ["cube_legend", "draw_labels", "draw_legend", "legend_line", "legend_names"]
