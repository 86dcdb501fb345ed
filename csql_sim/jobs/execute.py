"""The execute job: any planner's plan (or a rule base, or BFS) on the simulated arm, closed loop.

:func:`execute_problem` reads a blocks-world PDDL problem
(:func:`~csql_sim.core.files.pddl_import.read_problem`: the name mapping, the start, a full or
partial goal), then either

* reads an IPC plan file (:mod:`csql_sim.core.files.ipc_plan`) and checks it symbolically from
  the start: the first step that is not applicable is refused with its line number
  (:class:`~csql_sim.core.files.ipc_plan.PlanError`) before any physics runs; then replays it
  with :class:`PlanReplay`, which stops the run as soon as perception shows a state the
  plan does not predict; or
* follows a rule base (``rules``: :func:`~csql_sim.core.policies.loader.load_policy`) or the
  BFS planner (``planner="bfs"``) towards the goal state nearest the start
  (:meth:`~csql_sim.core.model.goal_spec.GoalSpec.nearest`), through :class:`GoalSetPolicy`.

2..30 cubes. Past six blocks the states are relational
(:class:`~csql_sim.core.state.world.State`): plans are checked with the relational
operators, lifted rules and GN1 aim at the target
:func:`~csql_sim.core.model.goal_spec.goal_target` derives from the start, and BFS and
ground rule files are refused with one line (they enumerate the world).

Execution is :func:`~csql_sim.sim.control.executor.run_physical_episode`: blocks move only through
the arm's contacts, and after every action the scene is perceived. The goal is
``reached`` when the final **perceived** state satisfies the goal's atoms. The result
(:class:`~csql_sim.jobs.execute_report.ExecuteResult`) says per step what was perceived.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from csql_sim.core.files.ipc_plan import PlanError, PlanStep, check_plan, parse_plan, read_plan
from csql_sim.core.files.pddl_import import MAX_PLANNED_BLOCKS, BlocksProblem, parse_problem_text, read_problem
from csql_sim.core.model.goal_spec import Atom, GoalSpec, atom_text, state_atoms
from csql_sim.core.policies.policy import Policy
from csql_sim.core.state.state import default_names
from csql_sim.core.state.world import MAX_BLOCKS, TABLE, Action, State
from csql_sim.infra.assets import BUILTIN_RULES, builtin_rules_path
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import write_or_keep
from csql_sim.infra.provenance import file_sha256, provenance, rules_source
from csql_sim.jobs.baselines import NAMED_POLICIES
from csql_sim.jobs.execute_report import ExecuteResult, StepReport
from csql_sim.jobs.execute_steps import BEFORE, final_state, policy_reports, replay_reports

if TYPE_CHECKING:
    from csql_sim.sim.video import VideoOptions

PlanInput = str | os.PathLike | Sequence[str]
"""A plan: the path of an IPC plan file, or a list of actions (``"(unstack a b)"`` or ``"unstack(A,B)"``)."""


@dataclass(frozen=True)
class VideoOut:
    """Where and how an episode's video is written."""

    path: str | os.PathLike
    options: VideoOptions
    progress: bool = False


class PlanReplay:
    """The policy that replays a checked plan, step by step, as long as perception agrees with it.

    Asked in a perceived state, it returns the plan's next action when the state is the
    one the plan predicts before that action (so a primitive that changed nothing is
    tried again), and None when the plan is done or perception diverged from it
    (:attr:`diverged`: the step index and the perceived state).
    """

    name = "plan"

    def __init__(self, actions: Sequence[Action], trace: Sequence[State]) -> None:
        self.actions, self.trace = tuple(actions), tuple(trace)
        n = self.trace[0].n
        self.blocks = n if n <= MAX_BLOCKS else None  # not a ground table past six
        self.next = 0
        self.issued = False
        self.diverged: tuple[int, State] | None = None
        self.last_seen: State | None = None

    def act(self, state: State, goal: State) -> Action | None:
        """The next action of the plan, or None (done, or diverged)."""
        self.last_seen = state
        i = self.next
        if self.issued and i < len(self.actions) and state == self.trace[i + 1]:
            i = self.next = i + 1
        self.issued = False
        if i >= len(self.actions):
            return None
        if state != self.trace[i]:
            self.diverged = (i, state)
            return None
        self.issued = True
        return self.actions[i]


class GoalSetPolicy:
    """A policy towards a (possibly partial) goal: None once the state satisfies it.

    Otherwise it asks ``inner`` for the way to a goal state: up to six blocks the one
    nearest the current state (recomputed from what is perceived, so a perturbed run aims
    anew); past six the fixed ``target`` (:func:`~csql_sim.core.model.goal_spec.goal_target`
    of the start), a full configuration the lifted rules or GN1 plan towards.
    """

    def __init__(self, inner: Policy, goal: GoalSpec, target: State | None = None) -> None:
        self.inner, self.goal, self.target = inner, goal, target
        self.name = getattr(inner, "name", "policy")
        self.blocks = goal.n if goal.enumerated else getattr(inner, "blocks", None)
        self.last_seen: State | None = None

    def act(self, state: State, goal: State) -> Action | None:
        """The inner policy's action towards the goal state it aims for, or None when satisfied."""
        self.last_seen = state
        if self.goal.satisfied(state):
            return None
        return self.inner.act(state, self.target if self.target is not None else self.goal.nearest(state))


def execute_problem(problem: str | os.PathLike, domain: str | os.PathLike | None = None,
                    plan: PlanInput | None = None, rules: str | os.PathLike | None = None,
                    planner: str | None = None, seed: int = 0, perception: str = "pose", perturb: bool = False,
                    video: str | os.PathLike | None = None, progress: bool = False,
                    video_options: VideoOptions | None = None) -> ExecuteResult:
    """Run a PDDL problem's plan (or a rule base's, or BFS's) on the simulated arm.

    Args:
        problem: the PDDL problem file.
        domain: its domain file (optional; checked to be a blocks-world domain).
        plan: an IPC plan file, or a list of actions.
        rules: a rule base instead of a plan (``"builtin"``: the shipped lifted rules).
        planner: ``"bfs"`` instead of a plan.
        seed: the episode's seed.
        perception: ``"pose"`` or ``"camera"``.
        perturb: jitter the start, maybe nudge a cube and drop a carried one.
        video: write the episode's video here (.mp4 or .gif) and its provenance ``<video>.json``.
        progress: progress bars on stderr.
        video_options: how the video is made (default :class:`~csql_sim.sim.video.VideoOptions`).

    Raises:
        CsqlError: one line for bad input (an unrepresentable problem, a step that is not
            applicable, with its line number), always before any physics runs.
    """
    bp = read_problem(problem, domain, max_blocks=MAX_PLANNED_BLOCKS)  # past 30 the arm's own refusal says why
    files = {"problem": _file(problem), "domain": _file(domain)}
    return execute_blocks(bp, plan=plan, rules=rules, planner=planner, seed=seed, perception=perception,
                          perturb=perturb, video=video, progress=progress, files=files, video_options=video_options)


def execute_task(start: str | State, goal: str | State | Sequence[str],
                 plan: PlanInput | None = None, rules: str | os.PathLike | None = None, planner: str | None = None,
                 seed: int = 0, perception: str = "pose", perturb: bool = False,
                 video: str | os.PathLike | None = None, progress: bool = False,
                 video_options: VideoOptions | None = None) -> ExecuteResult:
    """:func:`execute_problem` for a task in csql-sim's notation (objects ``a``, ``b``, ... are cubes A, B, ...).

    ``goal`` is a configuration (``"ABC"``) or a list of PDDL atoms (``["(on a b)"]``: a
    partial goal), for 2..30 cubes.
    """
    return execute_blocks(task_problem(start, goal), plan=plan, rules=rules, planner=planner, seed=seed,
                          perception=perception, perturb=perturb, video=video, progress=progress,
                          video_options=video_options)


def task_problem(start: str | State, goal: str | State | Sequence[str]) -> BlocksProblem:
    """A :class:`BlocksProblem` of a start configuration and a goal configuration or atoms."""
    from csql_sim.sim.world import parse_arm_state

    first = start if isinstance(start, State) else parse_arm_state(start)
    names = tuple(name.lower() for name in default_names(first.n))
    if isinstance(goal, (str, State)):
        end = goal if not isinstance(goal, str) else parse_arm_state(goal, first.n)
        spec = GoalSpec.of_state(end, names)
        return BlocksProblem(f"{first.notation()} -> {end.notation()}", names, first, spec, "4op")
    clear = [f"(clear {names[i]})" for i in range(first.n) if first.is_clear(i)]
    init = " ".join([atom_text(a) for a in sorted(state_atoms(first))] + clear)
    text = (f"(define (problem task) (:domain blocks) (:objects {' '.join(names)}) (:init {init}) "
            f"(:goal (and {' '.join(goal)})))")
    parsed = parse_problem_text(text, source="goal", max_blocks=MAX_PLANNED_BLOCKS)
    if parsed.objects == names:
        return parsed
    # past Z the problem's name order (a, aa, ab, b, ...) is not the cubes' (a .. z, aa, ...): the goal in cube order
    cube = [names.index(name) for name in parsed.objects]

    def back(atom: Atom) -> Atom:
        return atom[0], tuple(i if i == TABLE else cube[i] for i in atom[1])

    spec = GoalSpec(first.n, frozenset(map(back, parsed.goal.positive)), frozenset(map(back, parsed.goal.negative)),
                    names=names)
    return BlocksProblem(parsed.name, names, first, spec, parsed.style)


def execute_blocks(bp: BlocksProblem, plan: PlanInput | None = None, rules: str | os.PathLike | None = None,
                   planner: str | None = None, seed: int = 0, perception: str = "pose", perturb: bool = False,
                   video: str | os.PathLike | None = None, progress: bool = False,
                   files: dict[str, Any] | None = None, video_options: VideoOptions | None = None) -> ExecuteResult:
    """Run a read problem on the arm (the body of :func:`execute_problem`); 2..30 cubes.

    ``rules="builtin"`` names the shipped lifted rules (as ``--rules builtin`` does).
    """
    from csql_sim.sim.control import check_perception
    from csql_sim.sim.video import VideoOptions
    from csql_sim.sim.world import check_arm_blocks, check_tower_heights

    check_arm_blocks(bp.n)
    check_tower_heights(bp.start, bp.goal)
    if isinstance(rules, str) and rules == BUILTIN_RULES:
        rules = builtin_rules_path()
    check_perception(perception, bp.n)
    options = video_options or VideoOptions()
    if video is not None:
        from csql_sim.sim.video import resolve_renderer

        options.check(video)
        resolve_renderer(options.renderer)  # an unusable --renderer fails before any physics runs
    chosen = [k for k, v in (("plan", plan), ("rules", rules), ("planner", planner)) if v is not None]
    if len(chosen) != 1:
        raise CsqlError(f"give exactly one of a plan, a rule file or planner='bfs' (got {', '.join(chosen) or 'none'})")
    if planner is not None and planner not in ("bfs", *NAMED_POLICIES):
        raise CsqlError(f"planner must be one of bfs, {', '.join(NAMED_POLICIES)}; got {planner!r}")
    params = {**(files or {}), "objects": bp.mapping, "seed": seed, "perception": perception, "perturb": perturb,
              "video": None if video is None else os.fspath(video)}
    video_out = None if video is None else VideoOut(video, options, progress)
    if plan is not None:
        steps, source = _plan_steps(bp, plan)
        params["plan"] = source
        return _run_plan(bp, steps, source, seed, perception, perturb, video_out, progress, params)
    params.update(rules=rules_source(rules), planner=planner or "rules")
    return _run_policy(bp, rules, planner, seed, perception, perturb, video_out, progress, params)


def _plan_steps(bp: BlocksProblem, plan: PlanInput) -> tuple[list[PlanStep], dict[str, Any]]:
    allowed = bp.actions
    if isinstance(plan, (str, os.PathLike)):
        steps = read_plan(plan, bp.index, bp.n, allowed)
        return steps, {"kind": "plan", "file": os.fspath(plan), "sha256": file_sha256(plan)}
    items = [str(item) for item in plan]
    digest = hashlib.sha256(json.dumps(items).encode()).hexdigest()
    return parse_plan(items, bp.index, bp.n, "plan", allowed), {"kind": "plan", "file": None, "sha256": digest}


def _run_plan(bp: BlocksProblem, steps: list[PlanStep], source: dict[str, Any], seed: int, perception: str,
              perturb: bool, video: VideoOut | None, progress: bool, params: dict) -> ExecuteResult:
    """Check the plan symbolically, then replay it on the arm."""
    where = source["file"] or "plan"
    trace = check_plan(bp.start, steps, bp.objects, where)
    from csql_sim.sim.world import check_tower_heights

    check_tower_heights(bp.start, bp.goal, trace)
    actions = [a for step in steps for a in step.actions]
    source = {**source, "lines": len(steps), "actions": len(actions), "reaches_goal": bp.goal.satisfied(trace[-1])}
    replay = PlanReplay(actions, trace)
    episode = _episode(bp.start, trace[-1], replay, seed, perception, perturb, video, progress,
                       cap=2 * len(actions) + 8)
    final = final_state(episode, replay, bp.n)
    reports = replay_reports(steps, trace, episode, replay)
    reached = bp.goal.satisfied(final)
    reason = "" if reached else _plan_reason(bp, episode, replay, reports, final)
    return _result(bp, reached, reason, trace[-1], source, reports, final, episode, video, params)


def _run_policy(bp: BlocksProblem, rules: str | os.PathLike | None, planner: str | None, seed: int, perception: str,
                perturb: bool, video: VideoOut | None, progress: bool, params: dict) -> ExecuteResult:
    """Follow a rule base, BFS or a named baseline (GN1) to the goal on the arm."""
    from csql_sim.core.policies.loader import load_policy
    from csql_sim.sim.world import check_arm_policy

    named = planner is not None and planner != "bfs"
    if planner == "bfs":
        check_arm_policy(None, bp.n)  # BFS enumerates the world: refused past six blocks, with its reason
    inner = NAMED_POLICIES[planner]() if named else load_policy(rules, bp.n, progress=progress)
    target = bp.goal.nearest(bp.start)
    policy = GoalSetPolicy(inner, bp.goal, None if bp.goal.enumerated else target)
    check_arm_policy(policy, bp.n)
    kind = "rules" if rules is not None else planner or "bfs"
    source = {"kind": kind, "file": None if rules is None else os.fspath(rules)}
    episode = _episode(bp.start, target, policy, seed, perception, perturb, video, progress, cap=None)
    final = final_state(episode, policy, bp.n)
    reached = bp.goal.satisfied(final)
    reason = "" if reached else episode.reason or _unsatisfied(bp, final)
    return _result(bp, reached, reason, target, source, policy_reports(episode, bp.objects), final, episode, video,
                   params)


def _plan_reason(bp: BlocksProblem, episode: Any, replay: PlanReplay, reports: list[StepReport],
                 final: State | None) -> str:
    if replay.diverged is not None:
        k, seen = replay.diverged
        bad = next((r for r in reports if r.status == "diverged"), reports[k])
        if not bad.detail.startswith(BEFORE):  # perceived after the step just run
            return (f"perception diverged from the plan after {bad.where()}: the plan predicts {bad.expected}, "
                    f"perceived {bad.perceived}")
        return (f"perception diverged from the plan before {bad.where()}: the plan predicts "
                f"{replay.trace[k].notation()} there, perceived {seen.notation()}")
    if not episode.success and not episode.reason.startswith("policy gave no action"):
        return episode.reason
    return _unsatisfied(bp, final, "the plan ended; ")


def _unsatisfied(bp: BlocksProblem, final: State | None, prefix: str = "") -> str:
    if final is None:
        return f"{prefix}nothing was perceived"
    return f"{prefix}the perceived state {final.notation()} does not satisfy {' '.join(bp.goal.unsatisfied(final))}"


def _episode(start: State, target: State, policy: Policy, seed: int, perception: str, perturb: bool,
             video: VideoOut | None, progress: bool, cap: int | None) -> Any:
    from tqdm import tqdm

    from csql_sim.sim.control import run_physical_episode

    with tqdm(desc="executing", unit="action", disable=not progress, delay=1.0, leave=False) as bar:
        return run_physical_episode(start, target, policy, seed=seed, record=video is not None, perturb=perturb,
                                    perception=perception, max_actions=cap,
                                    fps=30 if video is None else video.options.sample_rate,
                                    on_action=lambda _k: bar.update())


def _result(bp: BlocksProblem, reached: bool, reason: str, target: State, source: dict, reports: list[StepReport],
            final: State | None, episode: Any, video: VideoOut | None, params: dict) -> ExecuteResult:
    result = ExecuteResult(reached=reached, reason=reason, problem=bp.name, objects=bp.objects,
                           start=bp.start.notation(), goal=bp.goal, target=target.notation(), source=source,
                           steps=reports, final=None if final is None else final.notation(), episode=episode,
                           parameters=params)
    if video is not None:
        result.video = _write_video(episode, video, params)
    return result


def _write_video(episode: Any, video: VideoOut, params: dict) -> Path:
    """The episode's video and its provenance sidecar (as ``csql-sim render`` writes them)."""
    from csql_sim.jobs.render import sidecar_path, sidecar_record
    from csql_sim.sim.video import resolve_renderer, video_frame_count, write_video
    from csql_sim.sim.world import cube_legend

    names = tuple(params["objects"])
    episode.recording.names = names  # the legend: PDDL object names, each with its cube's colour
    o = video.options
    path = write_video(episode.recording, video.path, o.width, o.height, o.fps, o.workers, progress=video.progress,
                       renderer=o.renderer)
    record = provenance(command="execute", **params, width=o.width, height=o.height, fps=o.fps, speed=o.speed,
                        renderer=resolve_renderer(o.renderer))
    info = {"file": path.name, "frames": video_frame_count(episode.recording, o.fps), "actions": episode.length,
            "success": episode.success, "reason": episode.reason, "legend": cube_legend(len(names), names)}
    write_or_keep([(sidecar_path(path), json.dumps(sidecar_record(record, info), indent=1) + "\n")])
    return path


def _file(path: str | os.PathLike | None) -> dict[str, Any] | None:
    if path is None:
        return None
    return {"file": os.fspath(path), "sha256": file_sha256(path)}


__all__ = ["ExecuteResult", "GoalSetPolicy", "PlanError", "PlanReplay", "StepReport", "execute_blocks",
           "execute_problem", "execute_task", "task_problem"]
