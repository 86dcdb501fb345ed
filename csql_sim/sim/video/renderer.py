"""Choosing the video renderer: pybullet's TinyRenderer (CPU) or its EGL plugin (OpenGL).

``tiny`` always works. ``egl`` loads pybullet's ``eglRenderer`` plugin into a replay
scene's client, as pybullet's examples do::

    pybullet.loadPlugin(pkgutil.get_loader("eglRenderer").get_filename(), "_eglRendererPlugin")

It renders headless through EGL: on a GPU where the driver offers one, otherwise on
Mesa's software rasteriser (llvmpipe). ``auto`` picks ``egl`` when the plugin loads in
a probe scene of this process, ``tiny`` otherwise. Both draw the same camera, so frames
match in framing and captions; the background colour and shading differ (OpenGL's clear
colour and lighting). Perception never uses EGL: the plugin draws every image of the
client it is loaded into, so it goes only into replay scenes.
"""

from __future__ import annotations

import atexit
import importlib.util
import subprocess
import sys
from functools import cache

from csql_sim.infra.errors import CsqlError
from csql_sim.sim.world.client import quiet_output
from csql_sim.sim.world.config import SimConfig
from csql_sim.sim.world.scene import Scene, projection_matrix, view_matrix

RENDERERS = ("auto", "tiny", "egl")
EGL_PLUGIN = "eglRenderer"
EGL_ENTRY = "_eglRendererPlugin"
WARM_UP_FRAMES = 2  # the plugin prints its driver's name on its first frames
PROBE_TIMEOUT_S = 60


class RendererError(CsqlError):
    """A renderer that cannot be used here."""


def egl_plugin_path() -> str | None:
    """The file of pybullet's ``eglRenderer`` extension module, or None where it is absent."""
    spec = importlib.util.find_spec(EGL_PLUGIN)
    return spec.origin if spec is not None and spec.origin else None


def _warm_up(scene: Scene) -> None:
    view = view_matrix((1.0, 0.0, 1.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    projection = projection_matrix(45.0, 1.0, 0.1, 3.0)
    for _ in range(WARM_UP_FRAMES):
        scene.render(view, projection, 8, 8)


def egl_scene(n: int, config: SimConfig | None = None) -> Scene | None:
    """A replay-only scene drawn by the EGL plugin (loaded quietly), or None if it does not load."""
    path = egl_plugin_path()
    if path is None:
        return None
    with quiet_output():
        scene = Scene(n, config, physics=False, renderer_plugin=(path, EGL_ENTRY))
        if not scene.opengl:
            scene.close()
            return None
        _warm_up(scene)
    atexit.register(close_quietly, scene)  # an open EGL client prints as the interpreter ends
    return scene


def close_quietly(scene: Scene) -> None:
    """Close a scene without the EGL plugin's "Destroy EGL OpenGL window." on stdout."""
    with quiet_output():
        scene.close()


def probe_egl() -> bool:
    """Load the EGL plugin into a two-cube replay scene of this process and draw; True on success."""
    scene = egl_scene(2)
    if scene is None:
        return False
    close_quietly(scene)
    return True


@cache
def egl_available() -> bool:
    """Whether the EGL plugin loads here, probed once per process in a child interpreter.

    A child, because a process that has started EGL (llvmpipe's threads) cannot safely
    fork the render workers afterwards: they hang.
    """
    if egl_plugin_path() is None:
        return False
    code = "import sys; from csql_sim.sim.video.renderer import probe_egl; sys.exit(0 if probe_egl() else 1)"
    try:
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, timeout=PROBE_TIMEOUT_S,
                              check=False)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return done.returncode == 0


def resolve_renderer(name: str) -> str:
    """``"tiny"`` or ``"egl"`` for a ``--renderer`` value; ``egl`` must load."""
    if name not in RENDERERS:
        raise RendererError(f"--renderer must be one of {', '.join(RENDERERS)}, got {name!r}")
    if name == "tiny":
        return "tiny"
    if egl_available():
        return "egl"
    if name == "auto":
        return "tiny"
    where = "pybullet has no eglRenderer module" if egl_plugin_path() is None else "it found no EGL display"
    raise RendererError(f"--renderer egl: pybullet's eglRenderer plugin did not load ({where}); "
                        "use --renderer tiny")
