"""The closed-loop executor: perceive, form the message, ask the policy, act, perceive again.

:func:`run_physical_episode` builds the world and runs an :class:`Episode`, whose named
steps are: draw the :class:`PerturbationPlan`, then repeat :meth:`Episode.step` (choose
an action, predict, execute, perceive), then :meth:`Episode.finish`. After every
primitive the perceived state is compared with the prediction of the
:class:`~csql_sim.core.model.world_model.WorldModel` passed in (the add-delete R-classifiers by
default). A mismatch is logged and the loop continues from the perceived state, up to a
cap on actions. Success is :meth:`PhysicalWorld.reached`: the task's
:meth:`~csql_sim.core.model.task.Task.is_success` on the perceived state, with the scene settled;
it is never inferred from the plan.

Up to six cubes the states are the enumerated world's, the messages the paper's form and
the default world model the ground R-classifiers. For 7..30 cubes
(:mod:`csql_sim.sim.world.arm_state`) the states are relational, the messages take the large
form, the world model reads the lifted rules, optimal lengths come from the exact
optimum (measuring only), and the policy must be lifted: BFS and ground rule bases are
refused before the scene is built. What ``--perturb`` does is :mod:`csql_sim.sim.control.perturbation`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

from csql_sim.core.model.search import BfsPolicy
from csql_sim.core.model.task import Task
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.policies.policy import Policy
from csql_sim.core.state.world import Action
from csql_sim.infra.errors import CsqlError
from csql_sim.sim.control.perturbation import PERTURBATION, Perturbation, PerturbationPlan, drop_hook, nudge
from csql_sim.sim.control.physical import PhysicalWorld, SimError
from csql_sim.sim.control.primitives import Status
from csql_sim.sim.perception.poses import Perceived
from csql_sim.sim.perception.rgbd import NO_NOISE, CameraNoise
from csql_sim.sim.video.recording import Caption, Recorder, Recording
from csql_sim.sim.world.arm_state import (
    ArmState,
    Messages,
    RelationalWorldModel,
    arm_optimal_length,
    check_arm_blocks,
    check_arm_policy,
    label,
    to_arm_state,
    world_model_for,
)
from csql_sim.sim.world.config import SimConfig
from csql_sim.sim.world.scene import Pose
from csql_sim.sim.world.tower_height import check_tower_heights

BLOCKED_PICK_TRIES = 2  # consecutive picks of a cube stopped by collisions before it is dragged clear


@dataclass(frozen=True, kw_only=True)
class StepRecord:
    """One executed action.

    Attributes:
        action: the action's name.
        message: the state message the policy saw (action slot empty).
        status: the primitive's outcome.
        predicted: the world model's next state (notation).
        perceived: what perception saw afterwards (notation, or the failure reason).
        sim_seconds: simulated time of the primitive.
    """

    action: str
    message: str
    status: Status
    predicted: str
    perceived: str
    sim_seconds: float
    recovery: bool = False  # a physical recovery (e.g. flatten(X)), not a blocks-world action

    @property
    def mismatch(self) -> bool:
        """True when perception disagrees with the world model (never for a recovery)."""
        return not self.recovery and self.predicted != self.perceived


@dataclass(kw_only=True)
class EpisodeResult:
    """The outcome of one physical episode (built by keyword; success and reason filled in as it runs)."""

    start: str
    goal: str
    seed: int
    optimal_length: int
    success: bool = False
    reason: str = ""
    steps: list[StepRecord] = field(default_factory=list)
    events: list[str] = field(default_factory=list)
    event_steps: list[int] = field(default_factory=list)  # the action (0-based) during which each event struck
    sim_seconds: float = 0.0
    final_poses: tuple[Pose, ...] = ()
    recording: Recording | None = None
    loop_steps: int = 0
    wall_seconds: dict[str, float] = field(default_factory=dict)  # setup, loop, stepping: benchmarks only

    @property
    def length(self) -> int:
        """Number of actions executed."""
        return len(self.steps)

    @property
    def optimal(self) -> bool:
        """A success whose executed plan had the optimal length."""
        return self.success and self.length == self.optimal_length

    @property
    def mismatches(self) -> list[StepRecord]:
        """The steps where perception disagreed with the world model."""
        return [s for s in self.steps if s.mismatch]

    @property
    def sim_seconds_per_action(self) -> float:
        """Mean simulated time of the executed primitives."""
        return sum(s.sim_seconds for s in self.steps) / max(1, len(self.steps))


def default_max_actions(start: ArmState, goal: ArmState) -> int:
    """The step cap: room for recovery beyond the optimal plan."""
    return 3 * arm_optimal_length(start, goal) + 12


def run_physical_episode(start: ArmState, goal: ArmState, policy: Policy | None = None, seed: int = 0,
                         record: bool = False, perturb: bool = False, perception: str = "pose",
                         max_actions: int | None = None, fps: int = 30, config: SimConfig | None = None,
                         perturbation: Perturbation = PERTURBATION,
                         world_model: WorldModel | RelationalWorldModel | None = None,
                         on_action: Callable[[int], None] | None = None,
                         camera_noise: CameraNoise = NO_NOISE) -> EpisodeResult:
    """Execute ``policy`` from ``start`` to ``goal`` on the simulated arm.

    Args:
        start: the start configuration (a held block is grasped for real): a State for
            2..30 cubes.
        goal: the goal configuration.
        policy: any Policy; the BFS planner when None (n <= 6 only: past six blocks the
            policy must be lifted, anything with ``act(state, goal)``).
        seed: seeds the episode's only generator.
        record: keep every body's pose at ``fps`` frames per simulated second.
        perturb: jitter the start scene, maybe nudge a cube and maybe drop the held cube.
        perception: ``"pose"`` or ``"camera"``.
        max_actions: cap on executed actions (default: 3 x optimal + 12).
        fps: recording frame rate in simulated time.
        config: scene settings (default: :func:`~csql_sim.sim.world.config.config_for` n).
        perturbation: what ``perturb`` does.
        world_model: predicts each next state and judges legality (default: the built-in
            R-classifiers, :meth:`WorldModel.for_blocks`, built once for this episode; past
            six blocks the lifted rules, :class:`~csql_sim.sim.world.arm_state.RelationalWorldModel`).
        on_action: called with the number of actions executed after each one (progress).
        camera_noise: sensor noise of camera perception.

    Raises:
        SimError: if the start state cannot be built, the arm cannot take n cubes, the start or
            the goal has a tower taller than the arm's limit, or the policy cannot plan for n
            (BFS or a ground rule base past six blocks).
    """
    if start.n != goal.n:
        raise SimError(f"start has {start.n} blocks but goal has {goal.n}")
    check_arm_blocks(start.n)
    check_tower_heights(start, goal)
    check_arm_policy(policy, start.n)
    start, goal = to_arm_state(start), to_arm_state(goal)
    task = Task(start, goal)
    cap = default_max_actions(start, goal) if max_actions is None else max_actions
    t_setup = time.perf_counter()
    with PhysicalWorld(start.n, seed, perception, config, camera_noise=camera_noise) as world:
        world.build(start, jitter=perturb and perturbation.jitter_start)
        episode = Episode(task, world, policy or BfsPolicy(), world_model or world_model_for(start.n),
                          cap=cap, seed=seed, perturbation=perturbation if perturb else None,
                          fps=fps if record else None, on_action=on_action)
        episode.result.wall_seconds["setup"] = episode.t_loop - t_setup
        return episode.run()


class Episode:
    """One closed-loop run on a built world: perceive, ask the policy, predict, act, perceive.

    Args:
        task: start and goal.
        world: the built physical world (its generator drives every random choice).
        policy: proposes each action.
        world_model: judges legality and predicts each next state.
        cap: most actions executed.
        seed: the episode's seed (reported).
        perturbation: what perturbs the episode, None for none.
        fps: recording frame rate, None for no recording.
        on_action: called with the number of actions executed after each one.
    """

    def __init__(self, task: Task, world: PhysicalWorld, policy: Policy,
                 world_model: WorldModel | RelationalWorldModel, *, cap: int,
                 seed: int, perturbation: Perturbation | None, fps: int | None,
                 on_action: Callable[[int], None] | None = None) -> None:
        self.task, self.world, self.policy, self.model, self.cap = task, world, policy, world_model, cap
        world.expect(task.goal)
        self.messages = Messages(task.goal)
        self.goal_index = self.messages.goal_index or 0  # the world model's goal argument (unused past six)
        optimal = arm_optimal_length(task.start, task.goal)
        self.result = EpisodeResult(start=task.start.notation(), goal=task.goal.notation(), seed=seed,
                                    optimal_length=optimal)
        self.t_loop = time.perf_counter()
        self.perturbation = perturbation
        self.plan = PerturbationPlan() if perturbation is None else PerturbationPlan.draw(world.rng, optimal,
                                                                                          perturbation)
        self.begin = world.scene.steps
        self.stepping_before = world.scene.step_wall
        self.perceived = world.perceive()
        self.on_action = on_action
        self.recorder: Recorder | None = None
        if fps is not None:
            first = Caption(0, message=self.messages.state(task.start), states=(("start", task.start),
                                                                                  ("goal", task.goal)))
            self.recorder = Recorder(world.scene, fps, first)
            world.add_step_hook(self.recorder)

    def run(self) -> EpisodeResult:
        """Step until success, failure or the cap, then finish."""
        while self.step():
            pass
        return self.finish()

    def step(self) -> bool:
        """One pass of the loop; False once the episode has ended (``result.reason`` says why, if failed)."""
        result, perceived = self.result, self.perceived
        state = perceived.state
        if state is None:
            if len(result.steps) < self.cap and (fix := _recover(self.world, perceived)) is not None:
                result.steps.append(fix)
                self.perceived = self.world.perceive()
                return True
            result.reason = f"perception failed: {perceived.reason}"
            return False
        message = self.messages.state(state)
        if result.steps:
            self._caption(Caption(len(result.steps), message=message, states=(("perceived", state),)))
        if self.world.reached(perceived, self.task.goal):
            result.success = True
            return False
        if len(result.steps) >= self.cap:
            result.reason = f"step cap of {self.cap} actions reached in {state.notation()}"
            return False
        action = self._choose(state)
        if action is None:
            return False
        try:
            predicted = self.model.predict_state(state, action, self.goal_index)
        except CsqlError as exc:
            result.reason = f"world model failed: {exc}"
            return False
        self._execute(state, message, action, predicted)
        return True

    def _caption(self, caption: Caption) -> None:
        if self.recorder is not None:
            self.recorder.caption = caption

    def _choose(self, state: ArmState) -> Action | None:
        """The policy's action if the world model finds it legal; None (with the reason set) otherwise."""
        try:
            action = self.policy.act(state, self.task.goal)
        except CsqlError as exc:
            self.result.reason = f"policy failed: {exc}"
            return None
        if action is None or not self.model.is_legal(state, action, self.goal_index):
            name = "no action" if action is None else label(action)
            self.result.reason = f"policy gave {name} in {state.notation()}"
            return None
        return action

    def _attempt(self, action: Action) -> int:
        """Consecutive failed tries of this very action just before now."""
        attempt = 0
        for earlier in reversed(self.result.steps):
            if earlier.action != label(action) or earlier.status.ok:
                break
            attempt += 1
        return attempt

    def _execute(self, state: ArmState, message: str, action: Action, predicted: ArmState) -> None:
        """Run the primitive (with any planned perturbation), perceive, and record the step."""
        world, result, pert = self.world, self.result, self.perturbation
        k = len(result.steps)
        hook = drop_hook(world, action, pert, result.events) if pert and k == self.plan.drop_at else None
        self._caption(Caption(k + 1, message=message, action=action))  # the message the policy saw, as reported
        attempt = self._attempt(action)
        if action.is_pick and attempt >= BLOCKED_PICK_TRIES and "collision" in result.steps[-1].status.reason:
            fix = _recover(world, self.perceived, blocked_pick=action.block)  # make room around it
            if fix is not None:
                result.steps.append(fix)
                self.perceived = world.perceive()
                return
        t0 = world.scene.steps
        status = world.execute(action, hook, attempt)
        if pert and k == self.plan.nudge_at:
            result.events.append(nudge(world, world.rng, pert))
        result.event_steps.extend([k] * (len(result.events) - len(result.event_steps)))
        self.perceived = world.perceive()
        seen = self.perceived.state.notation() if self.perceived.state is not None else self.perceived.reason
        result.steps.append(StepRecord(action=label(action), message=message, status=status,
                                       predicted=predicted.notation(), perceived=seen,
                                       sim_seconds=(world.scene.steps - t0) * world.config.physics.time_step))
        if self.on_action is not None:
            self.on_action(len(result.steps))

    def finish(self) -> EpisodeResult:
        """Fill in the timings, the final poses and the recording."""
        result, scene = self.result, self.world.scene
        result.loop_steps = scene.steps - self.begin
        result.wall_seconds["loop"] = time.perf_counter() - self.t_loop
        result.wall_seconds["stepping"] = scene.step_wall - self.stepping_before
        result.sim_seconds = result.loop_steps * self.world.config.physics.time_step
        result.final_poses = self.world.final_poses()
        if self.recorder is not None:
            last = self.recorder.caption
            if result.success:
                done = Caption(len(result.steps), "reached", last.message, states=(("goal", self.task.goal),))
            else:
                done = Caption(len(result.steps), f"FAILED: {result.reason}", last.message)
            self.recorder.caption = done
            result.recording = self.recorder.finish()
        return result


def _recover(world: PhysicalWorld, perceived: Perceived, blocked_pick: int | None = None) -> StepRecord | None:
    """Run a physical recovery (a cube resting flat nowhere, or a pick blocked by neighbours), if any."""
    t0 = world.scene.steps
    done = world.recover(perceived, blocked_pick)
    if done is None:
        return None
    name, status = done
    after = world.perceive()
    seen = after.state.notation() if after.state is not None else after.reason
    why = perceived.reason if blocked_pick is None else "picks keep colliding with neighbours"
    return StepRecord(action=name, message=why, status=status, predicted="", perceived=seen,
                      sim_seconds=(world.scene.steps - t0) * world.config.physics.time_step, recovery=True)


__all__ = ["Episode", "EpisodeResult", "Perturbation", "PerturbationPlan", "SimError", "StepRecord",
           "default_max_actions", "run_physical_episode"]
