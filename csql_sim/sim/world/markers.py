"""Fiducial markers: each cube carries the ArUco marker of its index on all six faces.

A cube's identity is the id of its marker (:func:`marker_id`), read by camera perception
(:mod:`csql_sim.sim.perception.rgbd`); its paint is cosmetic, a thin frame round each face,
and may repeat. The texture of a face (:func:`marker_image`) is, from the edge inwards: the
paint frame, a white quiet zone, and the marker itself (a black border cell round 4 x 4 data
cells). :func:`marker_texture` writes it once to a PNG cached in the temporary directory;
:func:`apply_markers` loads the textures into a scene's client and shows them on its cubes.

The dictionary is OpenCV's ``DICT_4X4_50``: the 4 x 4 family reads at the fewest pixels per
face, and the smallest dictionary with room for the arm's cubes keeps the codes furthest apart
(fewest misreads).
"""

from __future__ import annotations

import atexit
import os
import shutil
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import cv2
import numpy as np

from csql_sim.infra.errors import CsqlError
from csql_sim.sim.world.client import PhysicsClient

DICTIONARY_NAME = "DICT_4X4_50"
"""The ArUco dictionary of the cubes' markers (OpenCV's name)."""
DICTIONARY_SIZE = 50
"""Ids in :data:`DICTIONARY_NAME`: the most cubes that can carry distinct markers."""
MARKER_CELLS = 6
"""Cells across a marker: 4 data cells and a black border cell on either side."""
TEXTURE_FORMAT = 1
"""Version of the cached texture files (part of their folder name)."""
PRINTED = (1.0, 1.0, 1.0, 1.0)
"""The visual colour of a marked cube: white, so that the texture shows as printed."""


@dataclass(frozen=True)
class MarkerLayout:
    """How a marker is printed on a cube face, in marker cells.

    Attributes:
        frame: width of the paint frame at the face's edge, cells (>= 0).
        quiet: width of the white quiet zone round the marker, cells (>= 0.5: the detector needs it).
        cell_pixels: texture pixels per cell (>= 4).
    """

    frame: float = 0.5
    quiet: float = 0.75
    cell_pixels: int = 16

    @property
    def face_cells(self) -> float:
        """Cells across a whole face."""
        return MARKER_CELLS + 2 * (self.quiet + self.frame)

    @property
    def marker_fraction(self) -> float:
        """The marker's side over the face's side."""
        return MARKER_CELLS / self.face_cells


MARKER_LAYOUT = MarkerLayout()


def marker_id(i: int) -> int:
    """The marker id of cube ``i`` (its index).

    Raises:
        CsqlError: past :data:`DICTIONARY_SIZE` cubes.
    """
    if not 0 <= i < DICTIONARY_SIZE:
        raise CsqlError(f"cube {i} has no marker: {DICTIONARY_NAME} has ids 0..{DICTIONARY_SIZE - 1}")
    return i


@cache
def dictionary() -> cv2.aruco.Dictionary:
    """The ArUco dictionary of the markers."""
    return cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, DICTIONARY_NAME))


def marker_image(i: int, rgba: Sequence[float], layout: MarkerLayout = MARKER_LAYOUT) -> np.ndarray:
    """The face texture of cube ``i``: paint frame, quiet zone and marker (RGB uint8, square)."""
    px = layout.cell_pixels
    frame, quiet, marker = round(layout.frame * px), round(layout.quiet * px), MARKER_CELLS * px
    side = marker + 2 * (quiet + frame)
    paint = np.array([round(255 * c) for c in rgba[:3]], dtype=np.uint8)
    image = np.empty((side, side, 3), dtype=np.uint8)
    image[...] = paint
    image[frame:side - frame, frame:side - frame] = 255
    code = cv2.aruco.generateImageMarker(dictionary(), marker_id(i), marker)
    start = frame + quiet
    image[start:start + marker, start:start + marker] = code[:, :, None]
    return image


@cache
def _cache_dir() -> Path:
    """Where the textures are kept: the user's cache folder (``$XDG_CACHE_HOME`` or ``~/.cache``).

    Never the temporary folder, where runs leave nothing; where the cache cannot be written, a folder
    of this process's own, removed when it exits.
    """
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    folder = base / "csql-sim" / f"markers-v{TEXTURE_FORMAT}"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = tempfile.NamedTemporaryFile(dir=folder, suffix=".probe")  # noqa: SIM115 - closed at once
        probe.close()
        return folder
    except OSError:
        own = Path(tempfile.mkdtemp(prefix="csql-sim-markers-"))
        atexit.register(shutil.rmtree, own, True)
        return own


def _cached_png(name: str, draw: Callable[[], np.ndarray]) -> Path:
    """The PNG ``name`` in the texture cache, drawn and written (atomically) the first time."""
    path = _cache_dir() / name
    if path.exists():
        return path
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(suffix=".png", dir=path.parent)
    os.close(fd)
    try:
        if not cv2.imwrite(tmp, cv2.cvtColor(draw(), cv2.COLOR_RGB2BGR)):
            raise CsqlError(f"could not write the marker texture {path}")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path


def _paint_name(rgba: Sequence[float]) -> str:
    return "".join(f"{round(255 * c):02x}" for c in rgba[:3])


def marker_texture(i: int, rgba: Sequence[float], layout: MarkerLayout = MARKER_LAYOUT) -> Path:
    """A PNG of :func:`marker_image`, cached in the temporary directory."""
    shape = f"{layout.frame}-{layout.quiet}-{layout.cell_pixels}"
    name = f"{DICTIONARY_NAME}-{marker_id(i)}-{_paint_name(rgba)}-{shape}.png"
    return _cached_png(name, lambda: marker_image(i, rgba, layout))


def apply_markers(client: PhysicsClient, bodies: Sequence[int], colours: Sequence[Sequence[float]],
                  layout: MarkerLayout = MARKER_LAYOUT) -> None:
    """Print cube i's marker, framed in ``colours[i]`` (repeating), on every face of ``bodies[i]``.

    The bodies must have textured box visuals (``PhysicsClient.add_box(..., textured=True)``).
    """
    for i, body in enumerate(bodies):
        client.set_texture(body, client.load_texture(str(marker_texture(i, colours[i % len(colours)], layout))))


def erase_markers(client: PhysicsClient, bodies: Sequence[int], colours: Sequence[Sequence[float]]) -> None:
    """Paint the faces of ``bodies`` plain (no marker): tests of what perception does with unmarked cubes."""
    for body, rgba in zip(bodies, colours, strict=True):
        client.set_texture(body, client.load_texture(str(_plain_texture(rgba))))


def _plain_texture(rgba: Sequence[float]) -> Path:
    return _cached_png(f"plain-{_paint_name(rgba)}.png",
                       lambda: np.full((16, 16, 3), [round(255 * c) for c in rgba[:3]], dtype=np.uint8))


__all__ = ["DICTIONARY_NAME", "MARKER_LAYOUT", "MarkerLayout", "apply_markers", "dictionary", "erase_markers",
           "marker_id", "marker_image", "marker_texture"]
