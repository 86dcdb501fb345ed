"""Many PDDL problems on the arm: ``csql-sim evaluate --problems DIR`` (issue: any planner's plans).

Every problem file in a folder (``*.pddl`` that defines a problem, not a domain) is run
with :func:`~csql_sim.jobs.execute.execute_problem`: with its plan file from a plans
folder (``<stem>.plan``, ``<stem>.soln`` or ``<stem>.pddl.soln``, as Fast Downward and
pyperplan name them), or with a rule base, a named planner (GN1, GN2) or BFS. A problem whose plan is
refused (a step that is not applicable, an unrepresentable problem) is a failed row with
the refusal as its reason, so one bad plan does not hide the others' results; so is a
``*.pddl`` that cannot be read (a folder, a pipe, a device, a dangling link, a file too
large), read only through the guarded reader, which refuses those without reading them.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from csql_sim.core.files.pddl_import import MAX_PDDL_BYTES
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import InputFileError, read_text_file
from csql_sim.infra.provenance import provenance
from csql_sim.jobs.execute import execute_problem
from csql_sim.sim.world import cube_legend

PLAN_SUFFIXES = (".plan", ".soln", ".pddl.soln")
REPORT_FORMAT = "csql-sim problems report"


@dataclass(frozen=True)
class ProblemRun:
    """One problem's outcome.

    Attributes:
        problem: the problem file's name.
        plan: the plan file's name (None with rules or a planner).
        reached: the perceived final state satisfies the goal.
        actions: actions executed.
        reason: why not reached ("" when reached); a refusal before physics starts with ``refused:``.
        legend: object name -> cube colour (None when the problem was refused).
    """

    problem: str
    plan: str | None
    reached: bool
    actions: int
    reason: str
    legend: dict[str, str] | None = None


def problem_files(folder: str | os.PathLike) -> list[tuple[Path, str | None]]:
    """The problem files of ``folder``, sorted (domain files are skipped), each with why it cannot be read.

    Each ``*.pddl`` is read with the guarded reader (:func:`csql_sim.infra.files.read_text_file`:
    regular files only, at most :data:`~csql_sim.core.files.pddl_import.MAX_PDDL_BYTES`). One that
    cannot be read (a folder, a pipe, a device, a dangling link, a file too large) is kept
    with the reader's one-line reason (None for a readable file): it becomes a failed row.
    """
    root = Path(folder)
    if not root.is_dir():
        raise CsqlError(f"--problems {os.fspath(folder)!r} is not a folder")
    found = []
    for path in sorted(root.glob("*.pddl")):
        try:
            text = read_text_file(path, MAX_PDDL_BYTES, "PDDL problem")
        except InputFileError as exc:
            found.append((path, str(exc)))
            continue
        if "(define (domain" not in text.lower():
            found.append((path, None))
    if not found:
        raise CsqlError(f"--problems {os.fspath(folder)!r} holds no PDDL problem (*.pddl)")
    return found


def plan_file_name(problem: Path) -> str:
    """The name of ``problem``'s plan file as ``plan --problems --plan-out`` writes it: ``<stem>.plan``."""
    return problem.stem + PLAN_SUFFIXES[0]


def plan_file(problem: Path, plans: str | os.PathLike) -> Path:
    """The plan of ``problem`` in the plans folder (``<stem>.plan``, ``.soln`` or ``.pddl.soln``)."""
    for suffix in PLAN_SUFFIXES:
        candidate = Path(plans) / (problem.stem + suffix)
        if candidate.is_file():
            return candidate
    raise CsqlError(f"no plan for {problem.name} in {os.fspath(plans)!r} "
                    f"(looked for {', '.join(problem.stem + s for s in PLAN_SUFFIXES)})")


def evaluate_problems(folder: str | os.PathLike, plans: str | os.PathLike | None = None,
                      rules: str | os.PathLike | None = None, planner: str | None = None,
                      domain: str | os.PathLike | None = None, seed: int = 0, perception: str = "pose",
                      perturb: bool = False, progress: bool = False) -> list[ProblemRun]:
    """Run every problem of ``folder`` on the arm (its plan, a rule base's, GN1's, GN2's or BFS's), in name order."""
    if (plans is None) == (rules is None and planner is None):
        raise CsqlError("--problems needs exactly one of --plans DIR, --rules FILE or --planner (bfs, gn1, gn2)")
    files = problem_files(folder)
    if plans is not None:  # every plan found before any physics (an unreadable problem needs none)
        chosen = {p: plan_file(p, plans) for p, unreadable in files if unreadable is None}
    from tqdm import tqdm

    runs = []
    for problem, unreadable in tqdm(files, desc="problems", unit="problem", disable=not progress, leave=False,
                                    delay=1.0):
        if unreadable is not None:
            runs.append(ProblemRun(problem.name, None, False, 0, f"refused: {unreadable}"))
            continue
        plan = chosen[problem] if plans is not None else None
        try:
            result = execute_problem(problem, domain, plan=plan, rules=rules, planner=planner, seed=seed,
                                     perception=perception, perturb=perturb)
        except CsqlError as exc:
            runs.append(ProblemRun(problem.name, plan and plan.name, False, 0, f"refused: {exc}"))
            continue
        legend = cube_legend(result.blocks, result.objects)
        runs.append(ProblemRun(problem.name, plan and plan.name, result.reached, len(result.steps), result.reason,
                               legend))
    return runs


def problems_report(runs: list[ProblemRun], parameters: dict) -> dict:
    """The JSON report: counts, success rate and one row per problem, with provenance."""
    reached = sum(r.reached for r in runs)
    return {"format": REPORT_FORMAT, "version": 1, "problems": len(runs), "reached": reached,
            "success_rate": reached / len(runs) if runs else 0.0,
            "runs": [r.__dict__ for r in runs], "provenance": provenance(command="evaluate --problems", **parameters)}


def problems_lines(runs: list[ProblemRun]) -> list[str]:
    """The printed report: the success rate, then one line per problem."""
    reached = sum(r.reached for r in runs)
    lines = [f"{reached}/{len(runs)} problems reached on the arm ({100.0 * reached / len(runs):.1f} %)"]
    for r in runs:
        verdict = "reached" if r.reached else f"FAILED: {r.reason}"
        lines.append(f"  {r.problem:<24} {r.plan or '-':<24} {r.actions:>3} actions  {verdict}")
        if r.legend:
            lines.append("    legend: " + ", ".join(f"{k} = {v}" for k, v in r.legend.items()))
    return lines
