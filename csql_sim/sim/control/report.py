"""An episode as text: the verdict, every executed step and the perturbation events."""

from __future__ import annotations

from csql_sim.sim.control.executor import EpisodeResult


def episode_lines(result: EpisodeResult) -> list[str]:
    """The verdict, one line per executed step (message, action, simulated time, mismatch) and the events."""
    verdict = "reached the goal" if result.success else f"FAILED: {result.reason}"
    lines = [f"{result.start} -> {result.goal}: {verdict} in {result.length} actions "
             f"(optimal {result.optimal_length}), {result.sim_seconds:.2f} s simulated"]
    for step in result.steps:
        flag = "" if not step.mismatch else f"   mismatch: predicted {step.predicted}, perceived {step.perceived}"
        lines.append(f"  {step.message}  {step.action:<14} {step.sim_seconds:.2f} s{flag}")
    lines.extend(f"  perturbation: {event}" for event in result.events)
    return lines
