"""What an executed plan reports: per step what was perceived, and whether the goal was reached.

:class:`ExecuteResult` is the outcome of :func:`csql_sim.jobs.execute.execute_problem`: its
:meth:`~ExecuteResult.to_dict` is the JSON report (format ``csql-sim execute report``,
version 1), :meth:`~ExecuteResult.lines` the text the command prints and
:meth:`~ExecuteResult.explain` the failure message tests show.

Step statuses: ``ok`` (perceived what the plan predicts), ``retried`` (the same, after a
primitive that changed nothing was run again), ``failed`` (the primitive never achieved
the step), ``diverged`` (perception showed another state than the plan predicts: the run
stops there), ``not run`` (after a stop); for a planner's or rule base's own steps
``ok``, ``mismatch`` (perception differed from the world model's prediction, and the
policy went on from what it perceived) and ``recovery`` (a physical recovery such as
``flatten(A)``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from csql_sim.core.model.goal_spec import GoalSpec
from csql_sim.core.state.state import default_name
from csql_sim.sim.world import cube_legend, legend_line, parse_arm_state

REPORT_FORMAT = "csql-sim execute report"
REPORT_VERSION = 1
GOOD = ("ok", "retried")


@dataclass(frozen=True, kw_only=True)
class StepReport:
    """One executed (or not executed) action.

    Attributes:
        step: its position among the actions, from 1.
        line: the plan file's line it comes from (None: chosen by a planner or rule base).
        text: the plan's text of that line, e.g. ``(move-b-to-b a b c)``, or the action's name.
        action: the cube action, e.g. ``unstack(A,B)``.
        expected: the state the plan (or world model) predicts after it (notation).
        perceived: what perception saw after it (notation, or why perception failed); None if not run.
        status: see the module docstring.
        attempts: how many times the primitive ran.
        detail: retries, recoveries, the divergence.
    """

    step: int
    line: int | None
    text: str
    action: str
    expected: str | None
    perceived: str | None
    status: str
    attempts: int = 1
    detail: str = ""

    def to_dict(self) -> dict[str, Any]:
        """The step's JSON record."""
        return {"step": self.step, "line": self.line, "action": self.text, "cube_action": self.action,
                "expected": self.expected, "perceived": self.perceived, "status": self.status,
                "attempts": self.attempts, "detail": self.detail}

    def where(self) -> str:
        """``step 3 (line 4: (stack a b) = stack(A,B))``."""
        said = self.text if self.text == self.action else f"{self.text} = {self.action}"
        line = "" if self.line is None else f"line {self.line}: "
        return f"step {self.step} ({line}{said})"


@dataclass(kw_only=True)
class ExecuteResult:
    """The outcome of running a plan, a rule base or the planner on the simulated arm.

    Attributes:
        reached: the final **perceived** state satisfies the goal's atoms.
        reason: why not ("" when reached).
        problem: the problem's name (or the task, for a task given in notation).
        objects: the blocks' names; ``objects[i]`` is cube ``A + i``.
        start: the start state (notation).
        goal: the goal (full or partial).
        target: the goal state the executor ran to (the plan's end state, or the goal
            state nearest the start for a planner).
        source: what chose the actions: ``{"kind": "plan" | "rules" | "bfs", "file": ...}``.
        steps: one report per action.
        final: the last perceived state (notation), None if perception failed.
        episode: the executor's own record (timings, events, mismatches).
        video: the video written, if any.
        parameters: everything the run was given (for the provenance record).
    """

    reached: bool
    reason: str
    problem: str
    objects: tuple[str, ...]
    start: str
    goal: GoalSpec
    target: str
    source: dict[str, Any]
    steps: list[StepReport]
    final: str | None
    episode: Any = None
    video: Path | None = None
    parameters: dict[str, Any] = field(default_factory=dict)

    @property
    def blocks(self) -> int:
        """Number of blocks."""
        return len(self.objects)

    @property
    def mapping(self) -> dict[str, str]:
        """Object name -> cube name (A..Z, then AA, AB, ...)."""
        return {name: default_name(i) for i, name in enumerate(self.objects)}

    @property
    def failed_step(self) -> StepReport | None:
        """The first step that did not go as planned (diverged, failed), if any."""
        return next((s for s in self.steps if s.status in ("diverged", "failed")), None)

    def goal_text(self) -> str:
        """The goal's atoms, and its state or number of states."""
        if self.goal.partial:
            count = "" if self.goal.count is None else f": {self.goal.count} states"
            return f"{self.goal.text()} (partial{count}; ran to {self.target})"
        state = self.goal.states[0].notation()
        return f"{self.goal.text()} (= {state})" + ("" if state == self.target else f"; the plan ends in {self.target}")

    def to_dict(self) -> dict[str, Any]:
        """The JSON report (``provenance`` included)."""
        from csql_sim.infra.provenance import provenance

        ep = self.episode
        return {
            "format": REPORT_FORMAT, "version": REPORT_VERSION, "reached": self.reached, "reason": self.reason,
            "problem": self.problem, "blocks": self.blocks, "objects": self.mapping,
            "legend": cube_legend(self.blocks, self.objects), "start": self.start,
            "goal": {"atoms": self.goal.atom_texts(), "partial": self.goal.partial, "states": self.goal.count,
                     "target": self.target},
            "source": self.source, "final": self.final, "steps": [s.to_dict() for s in self.steps],
            "actions": 0 if ep is None else ep.length,
            "sim_seconds": 0.0 if ep is None else round(ep.sim_seconds, 6),
            "events": [] if ep is None else list(ep.events),
            "video": None if self.video is None else str(self.video),
            "provenance": provenance(command="execute", **self.parameters),
        }

    def lines(self) -> list[str]:
        """The text report: mapping, legend (name = colour), task, one line per step, the verdict."""
        out = [f"objects: {', '.join(f'{k} -> {v}' for k, v in self.mapping.items())}",
               legend_line(self.blocks, self.objects),
               f"start {self.start}; goal {self.goal_text()}; actions from {self._source_text()}"]
        for s in self.steps:
            line = "" if s.line is None else f"line {s.line}"
            seen = "" if s.perceived is None else f"perceived {s.perceived}"
            extra = f"  ({s.detail})" if s.detail else ""
            out.append(f"  {s.step:>3} {line:<8} {s.text:<24} {s.action:<13} {s.status:<9} {seen}{extra}".rstrip())
        out.extend(f"  perturbation: {e}" for e in (self.episode.events if self.episode is not None else ()))
        out.append(self.verdict())
        return out

    def verdict(self) -> str:
        """One line: reached or not, and why."""
        ep = self.episode
        plural = "" if ep is None or ep.length == 1 else "s"
        sim = "" if ep is None else f" ({ep.length} action{plural}, {ep.sim_seconds:.1f} s simulated)"
        if self.reached:
            return f"reached: the perceived state {self.final} satisfies the goal{sim}"
        return f"NOT reached: {self.reason}{sim}"

    def explain(self) -> str:
        """Why the goal was (not) reached: the failing step and what was perceived, then every step."""
        head = [self.verdict()]
        bad = self.failed_step
        if bad is not None:
            head.append(f"failed at {bad.where()}: {bad.status}; perceived {bad.perceived}"
                        + (f" ({bad.detail})" if bad.detail else ""))
        if not self.reached and self.final is not None:
            missing = self.goal.unsatisfied(parse_arm_state(self.final, self.blocks))
            if missing:
                head.append(f"goal atoms not satisfied by the perceived state {self.final}: {' '.join(missing)}")
        return "\n".join(head + self.lines()[:-1])

    def _source_text(self) -> str:
        kind, file = self.source.get("kind"), self.source.get("file")
        return f"{kind} {file}" if file else str(kind)

    def __repr__(self) -> str:
        """Short enough for pytest's assertion line: the verdict and the failing step."""
        bad = self.failed_step
        where = "" if bad is None else f"; {bad.where()} {bad.status}, perceived {bad.perceived}"
        state = "reached" if self.reached else f"not reached: {self.reason}"
        return f"<ExecuteResult {state}{where}; final {self.final}>"

