"""The physical blocks world behind the symbolic environment's Gymnasium interface.

Same observation (the perceived state's message), action space, ``action_mask``,
reward and termination as :class:`csql_sim.envs.symbolic.BlocksWorldEnv`, so one agent runs in
both. A legal action runs its primitive on the simulated Panda; the next observation is
whatever perception sees. Illegal actions are masked and leave the scene untouched.
``render_mode="rgb_array"`` returns a TinyRenderer image.
"""

from __future__ import annotations

import os

import numpy as np

from csql_sim.envs.render_mode import check_render_mode
from csql_sim.envs.symbolic import BlocksWorldEnv
from csql_sim.infra.errors import CsqlError
from csql_sim.sim.control import PhysicalWorld
from csql_sim.sim.perception import NO_NOISE, CameraNoise, Perceived, capture, render_camera
from csql_sim.sim.world import check_tower_heights

PHYSICS_SEED_BOUND = 2**31  # physics seeds are drawn from [0, 2**31)
MIN_IMAGE_SIDE, MAX_IMAGE_SIDE = 16, 4096  # rendered images' width and height, in pixels


def check_image_side(value: object, name: str) -> int:
    """A rendered image's ``width`` or ``height``: an integer in 16..4096, else a CsqlError naming it.

    The renderer itself is not asked: it returns empty images for 0, crashes the
    interpreter for negative sizes and aborts it for huge ones.
    """
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool) \
            and MIN_IMAGE_SIDE <= value <= MAX_IMAGE_SIDE:
        return int(value)
    raise CsqlError(f"{name} must be an integer in {MIN_IMAGE_SIDE}..{MAX_IMAGE_SIDE} pixels, got {value!r}")


class PhysicalBlocksEnv(BlocksWorldEnv):
    """Gymnasium environment of the n-block world executed on the simulated Franka Panda.

    Registered as ``csql_sim/PandaBlocks-v0``: ``gymnasium.make("csql_sim/PandaBlocks-v0",
    blocks=3, perception="camera", rules=None, render_mode="rgb_array")``.

    ## Description
    The symbolic environment's task (reach a goal configuration with pickup, putdown,
    stack and unstack) executed by pick-and-place primitives on a simulated arm with
    real contact grasping. The state is whatever perception sees after every primitive.

    ## Action Space
    ``Discrete(len(all_actions(n)))``; action ``i`` has the paper's action code ``i + 1``
    (18 for n = 3). ``info["action_mask"]`` (int8, 1 = legal) marks the actions
    legal in the perceived state; an illegal action leaves the scene untouched and sets
    ``info["illegal"]``.

    ## Observation Space
    ``Text``: the perceived state's message, as in
    :class:`csql_sim.envs.symbolic.BlocksWorldEnv`: for n <= 6 the paper's form with the
    goal code in the last field (``S0111000ttt0000C``); for n = 7..30 cubes the relational
    form (:func:`~csql_sim.core.state.relational_message.format_large_message`, ``3n + 5``
    characters), the goal written out as its on field and hand. With ``observation="numeric"``
    the same ``Dict`` of integer arrays as the symbolic environment's (:mod:`csql_sim.envs.numeric`).

    ## Starting State
    ``reset(options={"start": ..., "goal": ...})`` takes, for n <= 6, a
    :class:`~csql_sim.core.state.world.State`, a configuration (``"CBA"``) or a state index;
    for n = 7..30 a :class:`~csql_sim.core.state.world.State`, a configuration
    with names A..Z, AA, ... (``"JIHGFEDCBA"``) or a rank in ``0..state_count(n) - 1``
    (:func:`~csql_sim.core.state.state_count.unrank_state`). Either missing is drawn from
    ``np_random`` (past six uniformly by counting). Or ``reset(options={"problem": path})``:
    a blocks-world PDDL problem file of exactly n objects gives the start, the goal (possibly
    partial) and the blocks' names, as in :class:`csql_sim.envs.symbolic.BlocksWorldEnv` (not
    with ``start`` or ``goal``; bad input is a one-line CsqlError). The start scene is then
    built: towers placed at rest, a held block reached by a real grasp.

    ## Rewards
    1 on the step that reaches the goal, 0 otherwise.

    ## Episode End
    The episode ends if:

    - Termination: the perceived state is the goal (with a ``problem``: satisfies the
      goal's atoms) and every free cube is at rest (as :meth:`PhysicalWorld.reached` and
      the executor judge; success is never taken from the plan).
    - Truncation: perception fails (a cube off the table or tilted; ``info["failure"]``
      says why), or ``max_steps`` steps have been taken.

    ## Information
    ``step`` and ``reset`` return ``action_mask``, ``state`` (perceived), ``goal``, ``illegal``,
    ``names`` and ``goal_atoms`` (as the symbolic environment's) and ``failure`` (empty unless
    perception failed). :meth:`action_name` writes an action with the blocks' names.

    ## Seeding
    ``reset(seed=s)`` seeds ``np_random`` (Gymnasium's contract); from it are drawn, in
    this order, a missing goal, a missing start and then the physics seed (one integer
    in ``[0, 2**31)``) of the episode's :class:`PhysicalWorld`, whose one generator makes
    every random choice of the primitives (putdown spots). So ``reset(seed=s)`` with the
    same options fully determines the episode: the same actions give the same
    observations and the same final poses, in any process. A later ``reset()`` without
    a seed continues ``np_random``'s stream, so a seeded sequence of episodes is
    reproducible too; the first ``reset()`` of an env never seeded draws fresh entropy.

    Args:
        n: number of cubes, 2..30 (past 26 with ``observation="numeric"``).
        max_steps: steps before ``truncated``: a positive integer, or None (never).
        render_mode: ``"rgb_array"`` or None; any other mode raises ``gymnasium.error.UnsupportedMode``
            (``gymnasium.make`` wraps ``"human"`` and ``"rgb_array_list"`` around ``"rgb_array"``).
        perception: ``"pose"`` or ``"camera"``.
        width: rendered image width, an integer in 16..4096 pixels.
        height: rendered image height, an integer in 16..4096 pixels.
        camera_noise: sensor noise of camera perception.
        rules: a rule file whose precondition rules decide which actions are legal (the
            action mask; n <= 6 only, past six the STRIPS preconditions do); what an action
            does is up to the physics.
        observation: ``"message"`` (the perceived state's message) or ``"numeric"`` (the perceived
            state as integer arrays, :mod:`csql_sim.envs.numeric`).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 30}

    def __init__(self, n: int = 3, max_steps: int | None = None, render_mode: str | None = None,
                 perception: str = "pose", width: int = 640, height: int = 480,
                 camera_noise: CameraNoise = NO_NOISE,
                 rules: str | os.PathLike | None = None, observation: str = "message") -> None:
        check_render_mode(render_mode, self.metadata["render_modes"])
        self.width, self.height = check_image_side(width, "width"), check_image_side(height, "height")
        super().__init__(n, max_steps, None, rules, observation)
        self.render_mode = render_mode
        self.perception = perception
        self.camera_noise = camera_noise
        self.physical: PhysicalWorld | None = None
        self.physics_seed: int | None = None
        self.perceived = Perceived(None, "not reset")  # the last perception (an illegal action keeps it)
        self.failure = ""

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[str, dict]:
        """Choose start and goal as the symbolic env does, then build the start scene (see Seeding)."""
        super().reset(seed=seed, options=options)
        assert self.task is not None
        goal = self.task.goal if self.task.goal is not None else self.target
        check_tower_heights(self.current, goal)  # before any physics: the arm's tallest tower
        self.close()
        self.physics_seed = int(self.np_random.integers(PHYSICS_SEED_BOUND))
        self.physical = PhysicalWorld(self.n, self.physics_seed, self.perception, camera_noise=self.camera_noise)
        self.physical.build(self.current)
        self.physical.expect(self.target)  # the target state: the goal itself, or the one a partial goal aims at
        self.failure = ""
        self._sync()
        return self._obs(), self._info()

    def _sync(self) -> None:
        """Perceive; set the symbolic state to what perception sees (keep the old one on failure)."""
        assert self.physical is not None
        self.perceived = perceived = self.physical.perceive()
        if perceived.state is None:
            self.failure = perceived.reason
        else:
            self._set_current(perceived.state)

    def _reached(self) -> bool:
        """The perceived state satisfies the goal's atoms and every free cube is at rest (the executor's predicate)."""
        return self.task is not None and self.physical is not None and self.physical.reached(self.perceived, self.task)

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
        illegal = not self._legal(action)
        if not illegal:
            self.physical.execute(self._action(action))
            self._sync()
        self.steps += 1
        terminated = self._reached()
        truncated = not terminated and (bool(self.failure) or (self.max_steps is not None
                                                                and self.steps >= self.max_steps))
        return self._obs(), 1.0 if terminated else 0.0, terminated, truncated, self._info(illegal)

    def render(self) -> np.ndarray | None:  # type: ignore[override]
        """``rgb_array``: the scene from the rendering camera, (height, width, 3) uint8."""
        if self.render_mode != "rgb_array" or self.physical is None:
            return None
        rgb, _, _ = capture(self.physical.scene, render_camera(self.n), self.width, self.height)
        return rgb

    def close(self) -> None:
        """Release the physics client."""
        if self.physical is not None:
            self.physical.close()
            self.physical = None
