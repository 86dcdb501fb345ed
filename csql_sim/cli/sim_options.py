"""``render`` and ``evaluate`` options that another option makes meaningless: refused, never ignored.

Each check names the conflict in one line (exit 2) before any work:

* ``--camera-noise`` needs ``--perception camera``, and does not go with ``render --discovery``
  or ``evaluate --problems`` (neither takes camera noise);
* ``render --discovery`` takes no ``--planner``; without it, ``--transitions`` and ``--blocks``
  (the discovery's) are refused: an episode's blocks come from ``--start``;
* ``evaluate --problems`` takes no ``--pairs``, ``--seeds``, ``--blocks``, ``--workers``,
  ``--backend`` or ``--address`` (its problems run one after another, each with its blocks);
* ``evaluate --seed`` seeds a sample: with ``--pairs all`` (up to six blocks) it is refused;
* ``evaluate --workers`` with ``--address``: a Ray cluster uses its own CPUs.

Options whose default must be told from a value given are registered with ``default=None``;
:func:`check_evaluate_options` fills in their defaults after its checks.
"""

from __future__ import annotations

import argparse
import math

from csql_sim.core.state.world import MAX_BLOCKS
from csql_sim.infra.errors import CsqlError

DISCOVERY_BLOCKS = 3
"""``render --discovery --blocks`` (default)."""
DISCOVERY_TRANSITIONS = 16
"""``render --discovery --transitions`` (default)."""
EVALUATE_BLOCKS = 3
"""``evaluate --blocks`` (default)."""
NO_NOISE = (0.0, 0.0)
"""``--camera-noise`` not given (or 0): the camera's images as rendered."""


def _check_noise(args: argparse.Namespace, mode: str) -> None:
    """``--camera-noise`` only where camera images are made: with ``--perception camera``, and not in ``mode``."""
    if args.camera_noise == NO_NOISE:
        return
    if mode:
        raise CsqlError(f"--camera-noise does not apply to {mode}, which takes no camera noise")
    if args.perception != "camera":
        raise CsqlError(f"--camera-noise adds noise to camera images; it needs --perception camera "
                        f"(--perception {args.perception} takes no images)")


def check_render_options(args: argparse.Namespace) -> None:
    """Refuse, in one line, a ``render`` option the chosen mode would ignore."""
    _check_noise(args, "render --discovery" if args.discovery else "")
    if args.discovery:
        if args.planner is not None:
            raise CsqlError(f"--planner {args.planner} plans an episode; render --discovery attempts random actions")
        return
    given = [name for name, value in (("--transitions", args.transitions), ("--blocks", args.blocks))
             if value is not None]
    if given:
        raise CsqlError(f"{' and '.join(given)} go{'es' if len(given) == 1 else ''} with --discovery; without it "
                        f"render runs one episode from --start to --goal")


LARGE_DEFAULT_PAIRS = 20
"""``evaluate --pairs`` past six blocks when none is given: a sample of 20 pairs (``--seed`` 0)."""


def check_evaluate_options(args: argparse.Namespace) -> None:
    """Refuse, in one line, an ``evaluate`` option the chosen mode would ignore; then fill in the defaults."""
    if args.problems is not None:
        named = (("--pairs", args.pairs), ("--seeds", args.seeds), ("--blocks", args.blocks),
                 ("--workers", args.workers), ("--address", args.address))
        given = [name for name, value in named if value is not None]
        given += ["--backend"] * (args.backend != "processes") + ["--camera-noise"] * (args.camera_noise != NO_NOISE)
        if given:
            raise CsqlError(f"{', '.join(given)} {'does' if len(given) == 1 else 'do'} not apply to --problems, "
                            f"whose problems run one after another, each with its own blocks")
    else:
        _check_noise(args, "")
        blocks = args.blocks or EVALUATE_BLOCKS
        if args.seed is not None and args.pairs in (None, "all") and blocks <= MAX_BLOCKS:
            raise CsqlError("--seed seeds the sample of --pairs K; --pairs all runs every pair (each episode's seed "
                            "follows from its pair)")
        if args.workers is not None and args.address is not None:
            raise CsqlError(f"--workers {args.workers} sizes a local pool or Ray instance; the Ray cluster at "
                            f"--address {args.address} uses its own CPUs")
    args.blocks = args.blocks or EVALUATE_BLOCKS
    if args.pairs is None:  # every pair up to six blocks; past six, every pair is far too many: a sample
        args.pairs = "all" if args.blocks <= MAX_BLOCKS else LARGE_DEFAULT_PAIRS
    args.seeds = args.seeds or 1
    args.seed = args.seed or 0


def camera_noise_arg(text: str) -> tuple[float, float]:
    """Argparse type for --camera-noise ``DEPTH_MM[,COLOUR_LEVELS]``: (depth m, colour levels)."""
    try:
        values = [float(part) for part in text.split(",")]
    except ValueError:
        values = []
    if len(values) not in (1, 2) or not all(math.isfinite(v) and v >= 0 for v in values):
        raise argparse.ArgumentTypeError(f"expected DEPTH_MM or DEPTH_MM,COLOUR_LEVELS (numbers >= 0), got {text!r}")
    return values[0] / 1000.0, values[1] if len(values) == 2 else 0.0


def add_camera_noise(p: argparse.ArgumentParser) -> None:
    """``--camera-noise MM[,LEVELS]`` (``render`` and ``evaluate``)."""
    p.add_argument("--camera-noise", type=camera_noise_arg, default=NO_NOISE, metavar="MM[,LEVELS]",
                   help="camera perception noise: depth standard deviation in mm along the optical axis, "
                        "optionally colour standard deviation in 8-bit levels (e.g. 1.5,4; default none); "
                        "with --perception camera")
