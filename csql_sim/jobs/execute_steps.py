"""From the executor's record to the execute job's steps: which plan step each action was, and its fate.

The executor (:func:`~csql_sim.sim.control.executor.run_physical_episode`) records every
primitive it ran (:class:`~csql_sim.sim.control.executor.StepRecord`: the action, what was
perceived after it, recoveries marked as such). :func:`replay_reports` walks that record
along a replayed plan with the rule :class:`~csql_sim.jobs.execute.PlanReplay` follows: a
perceived state equal to the plan's next state completes the step; equal to the state
before it, the primitive is run again; anything else is a divergence, and the run stops.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from csql_sim.core.files.ipc_plan import PlanStep, ipc_action
from csql_sim.core.state.notation import parse_action_name
from csql_sim.core.state.world import State, WorldError, action_name
from csql_sim.jobs.execute_report import StepReport
from csql_sim.sim.world import parse_arm_state

BEFORE = "perceived before the step"
"""How a step's detail starts when perception diverged before the step was run (not after it)."""


def final_state(episode: Any, policy: Any, n: int) -> State | None:
    """The last perceived state of an episode (None when perception failed at the end).

    After a success it is the executor's goal; otherwise what was perceived after the last
    action, or (no action ran) the state the policy was last asked in.
    """
    if episode.success:
        return parse_arm_state(episode.goal, n)
    if episode.reason.startswith("perception failed"):
        return None
    if episode.steps:
        try:
            return parse_arm_state(episode.steps[-1].perceived, n)
        except WorldError:
            return None
    return policy.last_seen


def replay_reports(steps: Sequence[PlanStep], trace: Sequence[State], episode: Any,
                   replay: Any) -> list[StepReport]:
    """One report per action of a replayed plan (see the module docstring)."""
    flat = [(step, action) for step in steps for action in step.actions]
    rows: list[dict[str, Any]] = [{"attempts": 0, "perceived": None, "status": "not run", "notes": []} for _ in flat]
    j = 0
    for rec in episode.steps:
        if j >= len(flat):
            break
        row = rows[j]
        if rec.recovery:
            row["notes"].append(f"recovery {rec.action}: {rec.message}")
            continue
        row["attempts"] += 1
        row["perceived"] = rec.perceived
        if rec.perceived == trace[j + 1].notation():
            row["status"] = "ok" if row["attempts"] == 1 else "retried"
            j += 1
        elif rec.perceived == trace[j].notation():
            row["status"] = "failed"
            row["notes"].append(f"attempt {row['attempts']} changed nothing ({rec.status.reason or 'no reason'})")
        else:
            row["status"] = "diverged"
            row["notes"].append(f"the plan predicts {trace[j + 1].notation()}")
            break
    if replay.diverged is not None and rows and rows[min(replay.diverged[0], len(rows) - 1)]["status"] != "diverged":
        k, seen = replay.diverged
        rows[k].update(status="diverged", perceived=seen.notation())
        rows[k]["notes"].append(f"{BEFORE}; the plan predicts {trace[k].notation()} there")
    if j < len(flat) and rows[j]["status"] == "not run" and episode.success:
        rows[j]["notes"].append("the plan's final state was perceived before this step")
    return [StepReport(step=k + 1, line=step.line, text=step.text, action=action_name(action),
                       expected=trace[k + 1].notation(), perceived=row["perceived"], status=row["status"],
                       attempts=row["attempts"], detail="; ".join(row["notes"]))
            for k, ((step, action), row) in enumerate(zip(flat, rows, strict=True))]


def policy_reports(episode: Any, names: Sequence[str] | None = None) -> list[StepReport]:
    """One report per action a planner or rule base chose (recoveries included).

    ``names``: the problem's object names; each action's ``text`` is then written with them
    in IPC form, ``(unstack amber pearl)``, as a plan file's line would be (the cube action
    keeps the letters).
    """
    out = []
    for k, rec in enumerate(episode.steps):
        text = rec.action if rec.recovery or names is None else _named(rec.action, names)
        if rec.recovery:
            status, detail = "recovery", rec.message
        elif not rec.status.ok:
            status, detail = "failed", rec.status.reason
        else:
            status, detail = ("mismatch", f"predicted {rec.predicted}") if rec.mismatch else ("ok", "")
        out.append(StepReport(step=k + 1, line=None, text=text, action=rec.action,
                              expected=rec.predicted or None, perceived=rec.perceived, status=status, detail=detail))
    return out


def _named(action: str, names: Sequence[str]) -> str:
    """A cube action (``unstack(A,B)``) in IPC form with the objects' names; as it is if it is not one."""
    try:
        return ipc_action(parse_action_name(action, len(names)), names)
    except WorldError:
        return action
