"""The discovery job: rule discovery in the symbolic world or on the simulated arm.

Discovery (:mod:`csql_sim.discovery`) knows only the :class:`~csql_sim.discovery.world.ExplorableWorld`
protocol; this job builds the world asked for and runs the exploration in it.
"""

from __future__ import annotations

import numpy as np

from csql_sim.discovery.explore import DiscoveryResult, Exploration, Progress, explore
from csql_sim.discovery.world import SymbolicWorld
from csql_sim.infra.errors import CsqlError
from csql_sim.sim.video import Recording

WORLDS = ("physical", "symbolic")
DEFAULT_SETTINGS = Exploration()


def discover(n: int, world: str = "physical", seed: int = 0, settings: Exploration = DEFAULT_SETTINGS,
             perception: str = "pose", perturb: bool = False, progress: Progress | None = None) -> DiscoveryResult:
    """One discovery run on the simulated arm (``physical``) or the STRIPS world (``symbolic``).

    Raises:
        CsqlError: for an unknown world (the arm's own errors for a bad perception mode).
    """
    rng = np.random.default_rng(seed)
    if world == "symbolic":
        return explore(SymbolicWorld(n, rng, perturb=perturb), rng, settings, progress)
    if world != "physical":
        raise CsqlError(f"world must be one of {', '.join(WORLDS)}, got {world!r}")
    from csql_sim.sim.control import ArmWorld  # pybullet is loaded only for the arm

    with ArmWorld(n, rng, perception=perception, perturb=perturb) as arm:
        return explore(arm, rng, settings, progress)


def record_discovery(n: int, seed: int, transitions: int, fps: int, perception: str = "pose",
                     perturb: bool = False) -> tuple[DiscoveryResult, Recording]:
    """A short discovery episode on the arm, recorded: every attempt captioned, failures as such."""
    from csql_sim.sim.control import ArmWorld

    rng = np.random.default_rng(seed)
    with ArmWorld(n, rng, perception=perception, perturb=perturb, recorder_fps=fps) as arm:
        result = explore(arm, rng, Exploration(max_transitions=transitions))
        return result, arm.recorder.finish()
