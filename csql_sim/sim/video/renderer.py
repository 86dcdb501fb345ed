"""Choosing the video renderer: the flat painter, pybullet's TinyRenderer (CPU) or its EGL plugin (OpenGL).

``flat`` (:mod:`csql_sim.sim.video.painter`) always works and is the fast one on a CPU: a few
milliseconds a frame, where pybullet's renderers take about 0.4 s a 640x480 frame on one
core (the TinyRenderer, and the EGL plugin on Mesa's software rasteriser alike).
``tiny`` always works. ``egl`` loads pybullet's ``eglRenderer`` plugin into a replay
scene's client, as pybullet's examples do::

    pybullet.loadPlugin(pkgutil.get_loader("eglRenderer").get_filename(), "_eglRendererPlugin")

It renders headless through EGL: on a GPU where the driver offers one, otherwise on
Mesa's software rasteriser (llvmpipe). ``auto`` picks ``egl`` when the plugin loads in
a probe scene of this process on a GPU (the OpenGL renderer the plugin names is not a
software rasteriser: llvmpipe, softpipe, swrast), ``flat`` otherwise. Both draw the same camera, so frames
match in framing and captions; the background colour and shading differ (OpenGL's clear
colour and lighting). Perception never uses EGL: the plugin draws every image of the
client it is loaded into, so it goes only into replay scenes.
"""

from __future__ import annotations

import atexit
import glob
import importlib.util
import subprocess
import sys
from contextlib import nullcontext
from functools import cache

from csql_sim.infra.errors import CsqlError
from csql_sim.sim.world.client import quiet_output
from csql_sim.sim.world.config import SimConfig
from csql_sim.sim.world.scene import Scene, projection_matrix, view_matrix

RENDERERS = ("auto", "flat", "tiny", "egl")
RENDER_NODES, NVIDIA_NODES = "/dev/dri/renderD*", "/dev/nvidia[0-9]*"
SOFTWARE_GL = ("llvmpipe", "softpipe", "swrast")  # Mesa's CPU rasterisers: no faster than the painter
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


def egl_scene(n: int, config: SimConfig | None = None, quiet: bool = True) -> Scene | None:
    """A replay-only scene drawn by the EGL plugin (loaded quietly), or None if it does not load."""
    path = egl_plugin_path()
    if path is None:
        return None
    with quiet_output() if quiet else nullcontext():
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


def probe_egl(quiet: bool = True) -> bool:
    """Load the EGL plugin into a two-cube replay scene of this process and draw; True on success.

    ``quiet``: False lets the plugin print its driver's name (the probe's child process reads it).
    """
    scene = egl_scene(2, quiet=quiet)
    if scene is None:
        return False
    close_quietly(scene)
    return True


def egl_available() -> bool:
    """Whether the EGL plugin loads here (on a GPU or on a software rasteriser)."""
    return _egl_probe()[0]


def gpu_device() -> bool:
    """Whether this machine shows a GPU device node (a DRM render node or NVIDIA's): without one, EGL is software."""
    return bool(glob.glob(RENDER_NODES) or glob.glob(NVIDIA_NODES))


def egl_on_gpu() -> bool:
    """Whether the EGL plugin loads here on a GPU, not on one of Mesa's software rasterisers.

    Without a GPU device node the answer is no at once: the probe (a child interpreter
    starting EGL, seconds) runs only where there is a GPU to find.
    """
    if not gpu_device():
        return False
    loads, said = _egl_probe()
    return loads and not any(name in said for name in SOFTWARE_GL)


@cache
def _egl_probe() -> tuple[bool, str]:
    """Whether the EGL plugin loads, and what it printed (its OpenGL renderer's name), probed once per process.

    In a child interpreter, because a process that has started EGL (llvmpipe's threads)
    cannot safely fork the render workers afterwards: they hang.
    """
    if egl_plugin_path() is None:
        return False, ""
    code = "import sys; from csql_sim.sim.video.renderer import probe_egl; sys.exit(0 if probe_egl(quiet=False) else 1)"
    try:
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, timeout=PROBE_TIMEOUT_S,
                              check=False)
    except (OSError, subprocess.TimeoutExpired):
        return False, ""
    return done.returncode == 0, (done.stdout + done.stderr).decode("utf-8", "replace").lower()


def resolve_renderer(name: str) -> str:
    """``"flat"``, ``"tiny"`` or ``"egl"`` for a ``--renderer`` value; ``egl`` must load.

    ``auto``: ``egl`` on a GPU, else ``flat``.
    """
    if name not in RENDERERS:
        raise RendererError(f"--renderer must be one of {', '.join(RENDERERS)}, got {name!r}")
    if name in ("flat", "tiny"):
        return name
    if name == "auto":
        return "egl" if egl_on_gpu() else "flat"
    if egl_available():
        return "egl"
    where = "pybullet has no eglRenderer module" if egl_plugin_path() is None else "it found no EGL display"
    raise RendererError(f"--renderer egl: pybullet's eglRenderer plugin did not load ({where}); "
                        "use --renderer tiny")
