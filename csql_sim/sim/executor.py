"""The closed-loop executor: perceive, form the message, ask the policy, act, perceive again.

After every primitive the perceived state is compared with the world model's prediction
(the add-delete R-classifiers). A mismatch is logged and the loop continues from the
perceived state, up to a cap on actions. Success means the perceived state equals the
goal and the scene has settled; it is never inferred from the plan.
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass, field

import numpy as np

from csql_sim.classifiers import ClassifierList
from csql_sim.errors import CsqlError
from csql_sim.messages import action_code, format_state_message, parse_state_message
from csql_sim.planner import BfsPolicy, distance
from csql_sim.policy import Policy
from csql_sim.rules import domain_knowledge
from csql_sim.sim.config import DEFAULT_CONFIG, SimConfig
from csql_sim.sim.physical import PhysicalWorld, SimError
from csql_sim.sim.primitives import CarryHook, Status
from csql_sim.sim.recording import Recorder, Recording
from csql_sim.sim.scene import Pose
from csql_sim.world import Action, BlocksWorld, State, is_legal


@dataclass(frozen=True)
class Perturbation:
    """What --perturb does to an episode (all draws from the episode's generator)."""

    jitter_start: bool = True  # offset and rotate every cube of the start scene
    nudge_probability: float = 0.5  # chance of one physical nudge before some action
    nudge_force: float = 3.0  # N, horizontal, at the cube's centre
    nudge_steps: int = 10  # steps the force acts
    drop_probability: float = 0.5  # chance of opening the gripper during one carry
    drop_window: tuple[float, float] = (0.02, 0.1)  # fractions of the carry (arm still slow) to open in
    drop_clearance: float = 0.12  # m: open only where the cube falls clear of other cubes


PERTURBATION = Perturbation()


@dataclass(frozen=True)
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

    @property
    def mismatch(self) -> bool:
        """True when perception disagrees with the world model."""
        return self.predicted != self.perceived


@dataclass
class EpisodeResult:
    """The outcome of one physical episode."""

    start: str
    goal: str
    seed: int
    success: bool
    reason: str
    optimal_length: int
    steps: list[StepRecord] = field(default_factory=list)
    events: list[str] = field(default_factory=list)
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


def predict(state: State, action: Action, goal_index: int) -> State:
    """The world model's next state: the add-delete R-classifier the action activates.

    No fallback: exactly one rule fires for every legal action (tests check all 42 legal
    pairs of n=3 against :func:`csql_sim.world.successor`).
    """
    message = format_state_message(state, goal_index, BlocksWorld.of(state.n).action_index(action) + 1)
    return parse_state_message(_world_model(state.n).predict(message), state.n).state


@functools.cache
def _world_model(n: int) -> ClassifierList:
    return domain_knowledge(n)


def default_max_actions(start: State, goal: State) -> int:
    """The step cap: room for recovery beyond the optimal plan."""
    return 3 * distance(start, goal) + 12


def run_episode(start: State, goal: State, policy: Policy | None = None, seed: int = 0, record: bool = False,
                perturb: bool = False, perception: str = "pose", max_actions: int | None = None,
                fps: int = 30, config: SimConfig = DEFAULT_CONFIG,
                perturbation: Perturbation = PERTURBATION) -> EpisodeResult:
    """Execute ``policy`` from ``start`` to ``goal`` on the simulated arm.

    Args:
        start: the start configuration (a held block is grasped for real).
        goal: the goal configuration.
        policy: any Policy; the BFS planner when None.
        seed: seeds the episode's only generator.
        record: keep every body's pose at ``fps`` frames per simulated second.
        perturb: jitter the start scene, maybe nudge a cube and maybe drop the held cube.
        perception: ``"pose"`` or ``"camera"``.
        max_actions: cap on executed actions (default: 3 x optimal + 12).
        fps: recording frame rate in simulated time.
        config: scene settings.
        perturbation: what ``perturb`` does.

    Raises:
        SimError: if the start state cannot be built.
    """
    if start.n != goal.n:
        raise SimError(f"start has {start.n} blocks but goal has {goal.n}")
    policy = policy or BfsPolicy()
    world_index = BlocksWorld.of(start.n)
    goal_index = world_index.state_index(goal)
    optimal = distance(start, goal)
    cap = default_max_actions(start, goal) if max_actions is None else max_actions
    result = EpisodeResult(start.notation(), goal.notation(), seed, False, "", optimal)
    t_setup = time.perf_counter()
    with PhysicalWorld(start.n, seed, perception, config) as world:
        rng = world.rng
        world.build(start, jitter=perturb and perturbation.jitter_start)
        t_loop = time.perf_counter()
        nudge_at = drop_at = -1
        if perturb:
            if rng.random() < perturbation.nudge_probability:
                nudge_at = int(rng.integers(max(1, optimal)))
            if rng.random() < perturbation.drop_probability:
                drop_at = int(rng.integers(max(1, optimal)))
        begin = world.scene.steps
        stepping_before = world.scene.step_wall
        perceived = world.perceive()
        recorder = None
        if record:
            recorder = Recorder(world.scene, fps)
            world.add_step_hook(recorder)
        while True:
            state = perceived.state
            if state is None:
                result.reason = f"perception failed: {perceived.reason}"
                break
            message = format_state_message(state, goal_index)
            if recorder is not None:
                recorder.caption = f"{message}  {state.notation()}"
            if state == goal and world.is_settled():
                result.success = True
                break
            if len(result.steps) >= cap:
                result.reason = f"step cap of {cap} actions reached in {state.notation()}"
                break
            try:
                action = policy.act(state, goal)
            except CsqlError as exc:
                result.reason = f"policy failed: {exc}"
                break
            if action is None or not is_legal(state, action):
                name = "no action" if action is None else action.name()
                result.reason = f"policy gave {name} in {state.notation()}"
                break
            predicted = predict(state, action, goal_index)
            k = len(result.steps)
            hook = _drop_hook(world, action, perturbation, result.events) if k == drop_at else None
            if recorder is not None:
                code = action_code(action, start.n)
                recorder.caption = f"{action.name()}  {format_state_message(state, goal_index, int(code, 36))}"
            t0 = world.scene.steps
            attempt = 0
            for earlier in reversed(result.steps):  # consecutive failed tries of this very action
                if earlier.action != action.name() or earlier.status.ok:
                    break
                attempt += 1
            status = world.execute(action, hook, attempt)
            if k == nudge_at:
                result.events.append(_nudge(world, rng, perturbation))
            perceived = world.perceive()
            seen = perceived.state.notation() if perceived.state is not None else perceived.reason
            result.steps.append(StepRecord(action.name(), message, status, predicted.notation(), seen,
                                           (world.scene.steps - t0) * config.physics.time_step))
        result.loop_steps = world.scene.steps - begin
        result.wall_seconds = {"setup": t_loop - t_setup, "loop": time.perf_counter() - t_loop,
                               "stepping": world.scene.step_wall - stepping_before}
        result.sim_seconds = result.loop_steps * config.physics.time_step
        result.final_poses = world.final_poses()
        if recorder is not None:
            result.recording = recorder.finish()
    return result


def _nudge(world: PhysicalWorld, rng: np.random.Generator, pert: Perturbation) -> str:
    """Push a clear cube sideways with an external force (physics, not a reset).

    A lone cube slides; a cube on top of a tower may be pushed off it onto the table.
    """
    state = world.perceive().state
    if state is None:
        return "nudge skipped: nothing perceived"
    lone = [i for i in range(state.n) if state.is_clear(i)]
    if not lone:
        return "nudge skipped: no clear cube"
    block = lone[int(rng.integers(len(lone)))]
    scene = world.scene
    pos = np.asarray(scene.block_pose(block).position)
    others = [np.asarray(scene.block_pose(i).position) for i in range(state.n) if i != block]
    nearest = min(others, key=lambda p: float(np.linalg.norm(p[:2] - pos[:2])))
    away = math.atan2(pos[1] - nearest[1], pos[0] - nearest[0])
    angle = away + rng.uniform(-math.pi / 4, math.pi / 4)
    force = (pert.nudge_force * math.cos(angle), pert.nudge_force * math.sin(angle), 0.0)
    body = scene.block_body(block)
    for _ in range(pert.nudge_steps):
        centre = scene.block_pose(block).position
        scene.apply_force(body, force, centre)
        scene.step()
    world.settle()
    return f"nudged {'ABCDEF'[block]} towards {math.degrees(angle):.0f} deg"


def _drop_hook(world: PhysicalWorld, action: Action, pert: Perturbation, events: list[str]) -> CarryHook | None:
    """A carry hook that opens the gripper once the carried cube is clear of the others."""
    if action.is_pick:
        return None
    scene, panda = world.scene, world.panda
    fired = [False]

    def hook(fraction: float) -> None:
        if fired[0] or not pert.drop_window[0] <= fraction <= pert.drop_window[1]:
            return
        pos = np.asarray(scene.block_pose(action.block).position)
        for i in range(scene.n):
            if i != action.block and np.linalg.norm(np.asarray(scene.block_pose(i).position)[:2] - pos[:2]) < \
                    pert.drop_clearance:
                return
        panda.set_fingers(2 * scene.config.control.finger_open)
        fired[0] = True
        events.append(f"gripper opened while carrying {'ABCDEF'[action.block]}")

    return hook


__all__ = ["EpisodeResult", "Perturbation", "StepRecord", "predict", "run_episode", "SimError"]
