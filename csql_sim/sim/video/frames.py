"""Drawing a video's frames: the picture (flat painter or pybullet), the cubes' names, the top view, the caption.

:class:`ReplayRenderer` draws captioned frames of a recording for one :class:`View` (the
cameras, the frame size, the names); :mod:`csql_sim.sim.video` runs it in rendering
processes and encodes the frames.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache, lru_cache

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from csql_sim.sim.perception.camera import Camera, capture
from csql_sim.sim.video.painter import ArmShape, Painter, Projection
from csql_sim.sim.video.recording import Frame
from csql_sim.sim.video.renderer import close_quietly
from csql_sim.sim.video.replay import apply_snapshot, replay_scene
from csql_sim.sim.world.config import SimConfig
from csql_sim.sim.world.legend import draw_labels, draw_legend, legend_names
from csql_sim.sim.world.scene import Scene

CAPTION_HEIGHT = 0.09  # caption strip height as a fraction of the frame height


def caption_image(rgb: np.ndarray, text: str, legend: int | Sequence[str] = 0, full: bool = False) -> np.ndarray:
    """Draw ``text`` on a dark strip along the bottom (and, if given, the cubes' legend along the top).

    ``legend``: the cubes' names in cube order (or a count: the letters A, B, ...); each is
    drawn beside its colour's square, with the colour word when ``full``
    (:func:`csql_sim.sim.world.legend.draw_legend`). Videos name the cubes on the cubes instead.
    """
    img = Image.fromarray(rgb)
    strip = caption_strip(text, img.width, img.height)
    img.paste(strip, (0, img.height - strip.height))
    names = legend_names(legend) if isinstance(legend, int) else tuple(legend)
    if names:
        draw_legend(ImageDraw.Draw(img), img.width, max(8, strip.height * 0.6), names, full)
    return np.asarray(img)


@lru_cache(maxsize=64)
def caption_strip(text: str, width: int, height: int) -> Image.Image:
    """The caption strip of a ``width`` x ``height`` frame (drawn once per caption: frames share them)."""
    strip = max(12, int(height * CAPTION_HEIGHT))
    img = Image.new("RGB", (width, strip), (20, 20, 20))
    draw = ImageDraw.Draw(img)
    size = max(8, int(strip * 0.6))
    caption_font, line = fit_caption(draw, text, width - 12, size)
    parts = text.split("  ")
    if caption_font.size < size * 0.75 and len(parts) > 1 and strip >= 24:  # too small on one line: two lines
        lines = _two_lines(draw, parts, _font(int(strip * 0.4)))
        half = max(8, int(strip * 0.4))
        for k, part in enumerate(lines):
            font, part = fit_caption(draw, part, width - 12, half)
            draw.text((6, strip * 0.05 + k * strip * 0.47), part, fill=(255, 255, 255), font=font)
        return img
    draw.text((6, strip * 0.15), line, fill=(255, 255, 255), font=caption_font)
    return img


def _two_lines(draw: ImageDraw.ImageDraw, parts: list[str], font: ImageFont.ImageFont) -> tuple[str, str]:
    """The caption's parts (split at double spaces) in two lines, the longer as short as can be."""
    lines = [("  ".join(parts[:k]), "  ".join(parts[k:])) for k in range(1, len(parts))]
    return min(lines, key=lambda pair: max(draw.textlength(line, font=font) for line in pair))


def fit_caption(draw: ImageDraw.ImageDraw, text: str, width: float, size: int,
                smallest: int = 8) -> tuple[ImageFont.ImageFont, str]:
    """A font (``size`` or smaller, down to ``smallest``) and text that fit ``width`` pixels.

    A long caption (a 6-block tower's state, a long failure reason) first gets a smaller
    font; if it still does not fit, it is cut with an ellipsis, never drawn past the frame.
    """
    for points in range(size, smallest - 1, -1):
        font = _font(points)
        if draw.textlength(text, font=font) <= width:
            return font, text
    while text and draw.textlength(text + "...", font=font) > width:
        text = text[:-1]
    return font, text + "..."


@dataclass(frozen=True)
class View:
    """What every frame of one video is drawn with (the same in every rendering process).

    Attributes:
        width: frame width in pixels.
        height: frame height in pixels.
        camera: the main view (:func:`~csql_sim.sim.video.framing.goal_camera` of the recording by default).
        top: the second view, inset in the top right corner (None: none).
        names: the cubes' names, written on the cubes.
        total: the episode's actions (K of the captions).
        captions: the names the captions use (None: the cube letters).
        arm: the Panda's shape the flat painter draws (the recording's).
    """

    width: int
    height: int
    camera: Camera
    top: Camera | None
    names: tuple[str, ...]
    total: int
    captions: tuple[str, ...] | None = None
    arm: ArmShape | None = None


def inset_size(width: int, height: int) -> tuple[int, int]:
    """The top view's size: a third of the frame's width and height."""
    return max(8, width // 3), max(8, height // 3)


@cache
def _font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    return ImageFont.load_default(size=size)


class ReplayRenderer:
    """Renders captioned frames of recordings; owns one replay scene (and painter) per (n, config).

    Each rendering worker process owns exactly one, made by the pool's initializer
    (:func:`_init_render_worker`) and held in that process's ``_WORKER_RENDERER``; it
    lives as long as the worker. In-process rendering makes its own and closes it.

    Args:
        renderer: ``"flat"``, ``"tiny"`` or ``"egl"`` (resolved: :func:`csql_sim.sim.video.renderer.resolve_renderer`).
    """

    def __init__(self, renderer: str = "flat") -> None:
        self.renderer = renderer
        self._scenes: dict[tuple[int, SimConfig], Scene] = {}

    def scene(self, n: int, config: SimConfig) -> Scene:
        """The replay scene of ``n`` cubes and ``config`` (built on first use; pybullet's renderers only)."""
        key = (n, config)
        if key not in self._scenes:
            self._scenes[key] = replay_scene(n, config, self.renderer)
        return self._scenes[key]

    def render(self, n: int, config: SimConfig, frames: list[Frame], view: View) -> list[np.ndarray]:
        """Captioned RGB frames: each frame's poses seen by ``view.camera``, the cubes named, the top view inset.

        Captions read ``step k/K  <what>  <message>`` with K = ``view.total``.
        """
        painter = Painter(n, config, view.arm)
        main = Projection.of(view.camera, view.width, view.height)
        top = None if view.top is None else Projection.of(view.top, *inset_size(view.width, view.height))
        cube = config.physics.cube_size
        out = []
        for frame in frames:
            if self.renderer == "flat":
                img = painter.paint(frame.poses, frame.links, main)
            else:
                scene = self.scene(n, config)
                apply_snapshot(scene, frame.poses, frame.joints)
                img = Image.fromarray(capture(scene, view.camera, view.width, view.height)[0])
            xy, depth = main(np.asarray([p.position for p in frame.poses], dtype=float))
            draw_labels(img, xy, depth, view.names, main.focal * cube / np.maximum(depth, 1e-6))
            if top is not None:
                _inset(img, painter.paint(frame.poses, None, top))
            strip = caption_strip(frame.caption.text(view.total, view.captions), img.width, img.height)
            img.paste(strip, (0, img.height - strip.height))
            out.append(np.asarray(img))
        return out

    def close(self) -> None:
        """Release every replay scene's physics client."""
        for scene in self._scenes.values():
            close_quietly(scene)
        self._scenes.clear()


def _inset(img: Image.Image, small: Image.Image) -> None:
    """Paste ``small`` in the top right corner of ``img`` with a thin dark frame."""
    x = img.width - small.width - 4
    ImageDraw.Draw(img).rectangle((x - 2, 2, img.width - 2, small.height + 6), fill=(60, 60, 60))
    img.paste(small, (x, 4))


__all__ = ["CAPTION_HEIGHT", "ReplayRenderer", "View", "caption_image", "caption_strip", "fit_caption",
           "inset_size"]
