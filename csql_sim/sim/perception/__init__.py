"""Perception: from the scene, by poses or by cameras, to the symbolic state.

:mod:`.poses` reads the cubes' poses (with tolerances) and interprets them as a state,
:mod:`.camera` places and renders the cameras, :mod:`.rgbd` perceives from their depth and
colour images.

Contract: imports :mod:`csql_sim.sim.world`, ``core`` and ``infra``. Outside ``sim``, import
these names from this package.
"""

from csql_sim.sim.perception.camera import capture, render_camera
from csql_sim.sim.perception.poses import Perceived
from csql_sim.sim.perception.rgbd import NO_NOISE, CameraNoise

__all__ = ["CameraNoise", "NO_NOISE", "Perceived", "capture", "render_camera"]
