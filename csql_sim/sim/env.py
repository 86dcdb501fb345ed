"""The physical blocks world behind the symbolic environment's Gymnasium interface.

Same observation (the perceived state's message), action space, ``action_mask``,
reward and termination as :class:`csql_sim.env.BlocksWorldEnv`, so one agent runs in
both. A legal action runs its primitive on the simulated Panda; the next observation is
whatever perception sees. Illegal actions are masked and leave the scene untouched.
``render_mode="rgb_array"`` returns a TinyRenderer image.
"""

from __future__ import annotations

import numpy as np

from csql_sim.env import BlocksWorldEnv
from csql_sim.errors import CsqlError
from csql_sim.sim.camera import RENDER_CAMERA, capture
from csql_sim.sim.physical import PhysicalWorld


class PhysicalBlocksEnv(BlocksWorldEnv):
    """Gymnasium environment over the simulated arm.

    Args:
        n: number of blocks.
        max_steps: steps before ``truncated`` (None: never).
        render_mode: ``"rgb_array"`` or None.
        perception: ``"pose"`` or ``"camera"``.
        width: rendered image width.
        height: rendered image height.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 30}

    def __init__(self, n: int = 3, max_steps: int | None = None, render_mode: str | None = None,
                 perception: str = "pose", width: int = 640, height: int = 480) -> None:
        if render_mode not in (None, "rgb_array"):
            raise CsqlError(f"render_mode must be 'rgb_array' or None, got {render_mode!r}")
        super().__init__(n, max_steps, None)
        self.render_mode = render_mode
        self.perception = perception
        self.width, self.height = width, height
        self.physical: PhysicalWorld | None = None
        self.failure = ""

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[str, dict]:
        """Choose start and goal as the symbolic env does, then build the start scene."""
        super().reset(seed=seed, options=options)
        self.close()
        self.physical = PhysicalWorld(self.n, int(self.np_random.integers(2**31)), self.perception)
        self.physical.build(self.world.states[self.state])
        self.failure = ""
        self._sync()
        return self._obs(), self._info()

    def _sync(self) -> None:
        """Set the symbolic state to what perception sees (keep the old one on failure)."""
        assert self.physical is not None
        perceived = self.physical.perceive()
        if perceived.state is None:
            self.failure = perceived.reason
        else:
            self.state = self.world.state_index(perceived.state)

    def _info(self, illegal: bool = False) -> dict:
        info = super()._info(illegal)
        info["failure"] = self.failure
        return info

    def step(self, action: int) -> tuple[str, float, bool, bool, dict]:
        """Run the primitive of a legal ``action``; the observation is the perceived state."""
        if self.physical is None:
            raise CsqlError("call reset() before step()")
        if not self.action_space.contains(action):
            raise CsqlError(f"action must be 0..{self.action_space.n - 1}, got {action!r}")
        illegal = self.world.next_state[self.state][int(action)] < 0
        if not illegal:
            self.physical.execute(self.world.actions[int(action)])
            self._sync()
        self.steps += 1
        terminated = self.state == self.goal and not self.failure and self.physical.is_settled()
        truncated = not terminated and (bool(self.failure) or (self.max_steps is not None
                                                                and self.steps >= self.max_steps))
        return self._obs(), 1.0 if terminated else 0.0, terminated, truncated, self._info(illegal)

    def render(self) -> np.ndarray | None:  # type: ignore[override]
        """``rgb_array``: the scene from the rendering camera, (height, width, 3) uint8."""
        if self.render_mode != "rgb_array" or self.physical is None:
            return None
        rgb, _, _ = capture(self.physical.scene, RENDER_CAMERA, self.width, self.height)
        return rgb

    def close(self) -> None:
        """Release the physics client."""
        if self.physical is not None:
            self.physical.close()
            self.physical = None
