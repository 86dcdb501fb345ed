"""Control: what the arm does and the closed loop around it.

:mod:`.primitives` (pick, place; each a small callable returning a status) run under
:mod:`.guards` and :mod:`.recovery`; :mod:`.physical` is the world an episode acts in
(:class:`~csql_sim.sim.control.physical.PhysicalWorld`: act, then perceive); :mod:`.executor`
runs an episode (perceive, ask the policy, act, compare with the world model),
:mod:`.perturbation` disturbs it on purpose, :mod:`.exploration` lets rule discovery act on the
arm, :mod:`.report` prints an episode.

Contract: the top of ``sim``: imports the other sim families, ``discovery``, ``core`` and
``infra``. Outside ``sim``, import these names from this package.
"""

from csql_sim.sim.control.executor import EpisodeResult, run_physical_episode
from csql_sim.sim.control.exploration import ArmWorld
from csql_sim.sim.control.physical import PhysicalWorld, check_perception
from csql_sim.sim.control.report import episode_lines

__all__ = ["ArmWorld", "EpisodeResult", "PhysicalWorld", "check_perception", "episode_lines", "run_physical_episode"]
