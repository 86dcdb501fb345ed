"""Memory of the jobs that keep one record per item (an episode, a discovery attempt); refusal up front.

``evaluate`` keeps a summary of every episode for its report, and ``render --discovery``
keeps every recorded frame of every attempt until the video is written: their memory
grows with the count asked for. The limit is the one ``train`` checks by default (the
default of its ``--max-memory``: :func:`csql_sim.learners.training.costs.available_memory`,
above a process's own :data:`~csql_sim.learners.training.costs.PROCESS_BYTES`); a count whose
records cannot fit is refused before any work, in one line naming the count.
"""

from __future__ import annotations

from csql_sim.core.model.pairs import rounded
from csql_sim.infra.errors import CsqlError
from csql_sim.learners.training import PROCESS_BYTES, available_memory, format_size

EPISODE_BYTES = 4096
"""Peak memory per episode of ``evaluate``: its summary, its ``runs`` record and its JSON text (measured
4.0 kB at 6 blocks with ``tracemalloc``, the peak while the report is written)."""
FRAME_BYTES = 800
"""A recorded frame (:class:`csql_sim.sim.video.recording.Frame`): the arm's joints and the caption (measured) ..."""
FRAME_BYTES_PER_CUBE = 400
"""... and the pose of each cube (measured: 2.0 kB a frame at 3 cubes, 3.2 kB at 6)."""
GIF_PIXEL_BYTES = 4
"""A .gif holds every frame until it is closed, 4 bytes a pixel (measured: 0.3 MB a 320x240 frame)."""
ATTEMPT_SIM_SECONDS = 1.0
"""Simulated seconds of one discovery attempt (measured 0.75 s at 3 cubes, 35 of 40 attempts failed)."""
TRANSITION_BYTES = 2000
"""A discovery transition's log entry and its evidence."""


def check_fits_memory(count: int, item_bytes: int, what: str, advice: str) -> None:
    """Refuse ``count`` items of ``item_bytes`` each when they cannot fit the memory available.

    Args:
        count: how many records the job will keep.
        item_bytes: the memory of one.
        what: the items, named with their count (e.g. ``"100,000 episodes"``).
        advice: what to do instead.

    Raises:
        CsqlError: one line naming the count, the memory it needs and the limit.
    """
    need = PROCESS_BYTES + count * item_bytes
    limit = available_memory()
    if need > limit:
        raise CsqlError(f"{what} would keep about {format_size(need)} in memory ({format_size(item_bytes)} each), "
                        f"over the {format_size(limit)} memory available; {advice}")


def check_episodes(episodes: int, pairs: int, seeds: int) -> None:
    """``evaluate``: refuse ``pairs`` x ``seeds`` episodes whose summaries cannot fit the memory."""
    parts = [f"{pairs:,} pairs x {seeds:,} seeds"] if seeds > 1 else []
    parts += [rounded(episodes)] if episodes >= 10**6 else []
    what = f"{episodes:,} episodes" + (f" ({'; '.join(parts)})" if parts else "")
    check_fits_memory(episodes, EPISODE_BYTES, what, "give fewer --pairs or --seeds, or run several evaluations")


def discovery_transition_bytes(n: int, fps: int, width: int, height: int, gif: bool) -> int:
    """Memory one attempt of ``render --discovery`` keeps: its recorded frames (and .gif frames), its log entry."""
    frames = max(1, round(ATTEMPT_SIM_SECONDS * fps))
    frame = FRAME_BYTES + FRAME_BYTES_PER_CUBE * n + (GIF_PIXEL_BYTES * width * height if gif else 0)
    return frames * frame + TRANSITION_BYTES


def check_discovery(transitions: int, n: int, fps: int, width: int, height: int, gif: bool) -> None:
    """``render --discovery``: refuse ``--transitions`` whose recording cannot fit the memory."""
    per = discovery_transition_bytes(n, fps, width, height, gif)
    about = f" ({rounded(transitions)})" if transitions >= 10**6 else ""
    check_fits_memory(transitions, per, f"--transitions {transitions:,}{about} recorded",
                      "give fewer --transitions (the video shows each attempt)")
