"""Pictures of results: the evaluation figure and the shared atomic PNG writer (matplotlib, Agg)."""

from __future__ import annotations

import io
import os
from collections import Counter
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from csql_sim import __version__
from csql_sim.core.state.world import BlocksWorld
from csql_sim.infra.files import write_or_keep
from csql_sim.infra.outputs import PNG_TAG

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from csql_sim.jobs.evaluate import EpisodeSummary, EvalReport

OUTCOME_COLOURS = ("#2ca02c", "#ff7f0e", "#d62728")  # optimal, longer than optimal, failed
MATRIX_MAX_BLOCKS = 4  # 125 x 125 cells; n = 5 would have 866 x 866


def new_figure(width: float, height: float) -> Figure:
    """A matplotlib figure that needs no display."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height))


def png_bytes(fig: Figure, dpi: int = 110) -> bytes:
    """``fig`` as PNG bytes, tagged as ours: a ``Software`` text chunk naming csql-sim.

    The tag (:data:`csql_sim.infra.outputs.PNG_TAG`) says which tool and version drew it.
    """
    import matplotlib

    buffer = io.BytesIO()
    software = f"{PNG_TAG.decode()} {__version__} (matplotlib {matplotlib.__version__})"
    fig.savefig(buffer, format="png", dpi=dpi, metadata={"Software": software})
    return buffer.getvalue()


def save_figure(fig: Figure, path: str | os.PathLike, dpi: int = 110) -> Path:
    """Write ``fig`` as PNG atomically (kept in the temporary folder if that fails)."""
    return write_or_keep([(path, png_bytes(fig, dpi))])[0]


def outcome(run: EpisodeSummary) -> int:
    """0 optimal, 1 longer than optimal, 2 failed."""
    if not run.success:
        return 2
    return 0 if run.length == run.optimal_length else 1


def outcome_matrix(runs: list[EpisodeSummary], n: int) -> np.ndarray:
    """Start x goal matrix of the worst outcome over seeds; -1 where no episode ran."""
    world = BlocksWorld.of(n)
    index = {s.notation(): i for i, s in enumerate(world.states)}
    size = len(world.states)
    matrix = np.full((size, size), -1, dtype=int)
    for r in runs:
        i, j = index[r.start], index[r.goal]
        matrix[i, j] = max(matrix[i, j], outcome(r))
    return matrix


def _draw_matrix(ax: Axes, runs: list[EpisodeSummary], n: int) -> None:
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    matrix = outcome_matrix(runs, n)
    cmap = ListedColormap(["#eeeeee", *OUTCOME_COLOURS])
    ax.imshow(matrix + 1, cmap=cmap, vmin=0, vmax=3, interpolation="nearest")
    states = BlocksWorld.of(n).states
    if len(states) <= 30:
        labels = [s.notation() for s in states]
        ax.set_xticks(range(len(states)), labels, rotation=90, fontsize=6)
        ax.set_yticks(range(len(states)), labels, fontsize=6)
    ax.set_xlabel("goal")
    ax.set_ylabel("start")
    ax.set_title("outcome per start x goal")
    names = ("optimal", "longer than optimal", "failed", "not run")
    colours = (*OUTCOME_COLOURS, "#eeeeee")
    ax.figure.legend(handles=[Patch(color=c, label=t) for c, t in zip(colours, names, strict=True)],
                     fontsize=8, loc="lower left", ncol=4, title="start x goal outcome (worst over seeds)")


def _draw_lengths(ax: Axes, runs: list[EpisodeSummary]) -> None:
    ok = Counter((r.optimal_length, r.length) for r in runs if r.success)
    failed = sum(not r.success for r in runs)
    if ok:
        xs, ys, counts = zip(*((x, y, c) for (x, y), c in sorted(ok.items())), strict=True)
        sizes = 20 + 180 * np.sqrt(np.asarray(counts) / max(counts))
        colours = [OUTCOME_COLOURS[0] if x == y else OUTCOME_COLOURS[1] for x, y in zip(xs, ys, strict=True)]
        ax.scatter(xs, ys, s=sizes, c=colours, alpha=0.8, edgecolors="black", linewidths=0.4)
        for x, y, c in zip(xs, ys, counts, strict=True):
            ax.annotate(str(c), (x, y), fontsize=6, ha="center", va="center")
        top = max(max(xs), max(ys)) + 1
        ax.plot([0, top], [0, top], color="grey", lw=0.8, ls=":", label="executed = optimal")
        ax.legend(fontsize=7, loc="upper left")
    ax.set_xlabel("optimal plan length (BFS)")
    ax.set_ylabel("executed actions")
    _integer_ticks(ax)
    ax.set_title(f"executed vs optimal length ({failed} failed, not shown)")
    ax.grid(alpha=0.3)


def _draw_perturbations(ax: Axes, runs: list[EpisodeSummary]) -> None:
    hits = [(e.step, e.what.split()[0], r.success) for r in runs for e in r.events]
    struck = [r for r in runs if r.events]
    recovered = sum(r.success for r in struck)
    ax.set_title(f"perturbations: where they struck ({recovered}/{len(struck)} episodes recovered)")
    if not hits:
        ax.text(0.5, 0.5, "no perturbations\n(run evaluate with --perturb)", ha="center", va="center",
                transform=ax.transAxes)
        ax.set_axis_off()
        return
    last = max(h[0] for h in hits) + 1
    steps = np.arange(last)
    bottom = np.zeros(last)
    series = (("nudged", True, "#1f77b4", "nudge, recovered"), ("gripper", True, "#9467bd", "drop, recovered"),
              (None, False, OUTCOME_COLOURS[2], "episode failed"))
    for kind, recovered, colour, label in series:
        counts = np.zeros(last)
        for step, what, success in hits:
            if success == recovered and (kind is None or what == kind):
                counts[step] += 1
        ax.bar(steps + 1, counts, bottom=bottom, color=colour, label=label)
        bottom += counts
    ax.set_xlabel("during action k of the episode")
    ax.set_ylabel("perturbation events")
    _integer_ticks(ax)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, axis="y")


def _integer_ticks(ax: Axes) -> None:
    """Counts on both axes: whole-number ticks only."""
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))


def write_evaluation_png(report: EvalReport, path: str | os.PathLike) -> Path:
    """The evaluation figure: outcome matrix (n <= 4), executed vs optimal length, perturbations."""
    n = int(report.config.get("blocks", 3))
    matrix = n <= MATRIX_MAX_BLOCKS
    fig = new_figure(16 if matrix else 11, 5.6)
    axes = list(fig.subplots(1, 3 if matrix else 2))
    if matrix:
        _draw_matrix(axes.pop(0), report.runs, n)
    _draw_lengths(axes[0], report.runs)
    _draw_perturbations(axes[1], report.runs)
    rules = (report.config.get("rules") or {}).get("file") or "BFS planner"
    fig.suptitle(f"evaluate: {report.successes}/{report.episodes} succeeded, {report.optimal} optimal "
                 f"({n} blocks, {rules}, perception {report.config.get('perception', 'pose')}"
                 f"{', perturbed' if report.config.get('perturb') else ''})")
    fig.tight_layout(rect=(0, 0.08 if matrix else 0, 1, 1))
    return save_figure(fig, path)
