"""Camera perception by markers at 10, 20 and 30 cubes: reads, pose error, misidentified and unseen cubes.

Regenerates docs/results/arm.md (the table "Perception by markers").

Each scene is a table with the Panda at home and n marked cubes (:mod:`csql_sim.sim.world.markers`)
standing in towers up to ``--max-height`` high on spots within the arm's reach
(:func:`marker_scene`, a static scene this script owns: cubes placed, never stepped). Each
frame is one camera perception (:func:`csql_sim.sim.perception.rgbd.locate_cubes`, the views
of :func:`csql_sim.sim.perception.camera.perception_cameras`) with sensor noise drawn afresh.
Per size it prints: marker reads per frame (plausible reads, all views), reads whose id is
not the cube the renderer drew under the read's centre (noiseless images, once per scene; in
brackets, the same for perception's second decoding, ``RETRY_LIMITS``), pose error of the seen cubes
(mean and max, mm), misidentified cubes (a seen cube whose estimate is nearer another
cube's centre than its own, or more than half a cube from its own), unseen cubes, frames
whose relational state (``on``, ``on-table``) equals the scene's, and CPU seconds per frame
(this process's time: steadier than wall time on a shared machine).

    python benchmarks/perception_markers.py                                   # 10, 20, 30 cubes, 5 scenes x 2 frames
    python benchmarks/perception_markers.py --sizes 30 --scenes 10 --frames 1 --noise 1.5,4 --seed 1

Bad input is one line on stderr and exit status 2.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from csql_sim.core.state.world import TABLE
from csql_sim.infra.errors import CsqlError
from csql_sim.sim.perception.camera import CAMERA_TOLERANCES, Camera, perception_cameras
from csql_sim.sim.perception.fiducials import READ_LIMITS, RETRY_LIMITS, read_markers
from csql_sim.sim.perception.poses import Observation, interpret
from csql_sim.sim.perception.rgbd import CameraNoise, locate_cubes
from csql_sim.sim.world.client import PhysicsClient, quaternion_from_euler
from csql_sim.sim.world.config import COLOURS, WIDE_CONFIG
from csql_sim.sim.world.markers import PRINTED, apply_markers
from csql_sim.sim.world.scene import PANDA_URDF

SPOT_RADII = (0.46, 0.60, 0.74)  # m from the arm's base: three rows of spots
SPOT_SPACING = 0.13  # m between neighbouring spots on a row
HAND_HOME_XY = (0.463, 0.0)  # m: under the Panda's hand at home (fingers 0.40-0.45 m up): no tower there
HAND_CLEARANCE = 0.12  # m


@dataclass
class MarkerScene:
    """A static scene: its client, the cubes' bodies, true centres and supports (cube index or TABLE)."""

    client: PhysicsClient
    bodies: list[int]
    centres: np.ndarray
    support: tuple[int, ...]


def spots() -> list[tuple[float, float]]:
    """Table spots within the Panda's reach, on three arcs about its base (+-60 degrees), none under the hand."""
    out = []
    for r in SPOT_RADII:
        k = int(r * math.radians(120) / SPOT_SPACING)
        out += [(r * math.cos(a), r * math.sin(a)) for a in np.linspace(-math.radians(60), math.radians(60), k + 1)]
    return [xy for xy in out if math.dist(xy, HAND_HOME_XY) > HAND_CLEARANCE]


def marker_scene(n: int, max_height: int, rng: np.random.Generator) -> MarkerScene:
    """n marked cubes in towers of 1..max_height on randomly chosen spots (the Panda at home)."""
    physics = WIDE_CONFIG.physics
    client = PhysicsClient(physics)
    client.add_box(physics.table_half_extents, 0.0, (0.72, 0.6, 0.45, 1.0), physics.table_centre)
    panda = client.load_fixed_urdf(PANDA_URDF)
    for j, q in enumerate(WIDE_CONFIG.control.home_joints):
        client.reset_joint(panda, j, q)
    size = physics.cube_size
    bodies = [client.add_box((size / 2,) * 3, 0.0, PRINTED, (0.0, 0.0, -1.0), True) for _ in range(n)]
    apply_markers(client, bodies, COLOURS)
    order = rng.permutation(n)
    places = spots()
    chosen = rng.permutation(len(places))
    centres, support = np.zeros((n, 3)), [TABLE] * n
    k = t = 0
    while k < n:
        least = math.ceil((n - k) / (len(places) - t))  # the cubes left must fit on the spots left
        height = int(rng.integers(least, min(max_height, n - k) + 1))
        x, y = places[chosen[t]]
        yaw = math.atan2(y, x) + rng.uniform(-0.15, 0.15)
        for level in range(height):
            cube = int(order[k + level])
            centres[cube] = (x, y, size / 2 + level * size)
            support[cube] = TABLE if level == 0 else int(order[k + level - 1])
            client.set_body_pose(bodies[cube], tuple(centres[cube]), quaternion_from_euler((0.0, 0.0, yaw)))
        k, t = k + height, t + 1
    return MarkerScene(client, bodies, centres, tuple(support))


@dataclass
class Tally:
    """The figures of one size, summed over frames."""

    frames: int = 0
    reads: int = 0
    wrong_reads: int = 0
    wrong_retry: int = 0  # the same, decoded with RETRY_LIMITS (perception's second decoding)
    errors: list[float] = field(default_factory=list)
    misidentified: int = 0
    unseen: int = 0
    states: int = 0
    seconds: float = 0.0
    failures: list[str] = field(default_factory=list)


def perceive_frame(scene: MarkerScene, cameras: tuple[Camera, ...], noise: CameraNoise,
                   rng: np.random.Generator, tally: Tally, check_ids: bool) -> None:
    """One perception of the scene, added to ``tally`` (``check_ids``: also check the reads' ids)."""
    n, size = len(scene.bodies), WIDE_CONFIG.physics.cube_size

    def render(camera: Camera) -> tuple[np.ndarray, np.ndarray]:
        return scene.client.render(*camera.matrices(), camera.width, camera.height)[:2]

    began = time.process_time()  # CPU time of this process: the renders, the noise and the reading
    blocks = locate_cubes(render, cameras, n, size, noise, rng)
    tally.seconds += time.process_time() - began
    if check_ids:  # the noiseless images' reads against the renderer's ids (not timed)
        for camera in cameras:
            rgb, _, ids = scene.client.render(*camera.matrices(), camera.width, camera.height, segmentation=True)
            for read in read_markers(rgb, n, READ_LIMITS):
                col, row = np.rint(read.centre).astype(int)
                tally.wrong_reads += int(ids[row, col] != scene.bodies[read.cube])
            for read in read_markers(rgb, n, RETRY_LIMITS):
                col, row = np.rint(read.centre).astype(int)
                tally.wrong_retry += int(ids[row, col] != scene.bodies[read.cube])
    tally.frames += 1
    tally.reads += sum(b.reads for b in blocks)
    for i, b in enumerate(blocks):
        if not b.visible:
            tally.unseen += 1
            continue
        dist = np.linalg.norm(scene.centres - np.asarray(b.position), axis=1)
        tally.errors.append(1000 * dist[i])
        tally.misidentified += int(int(np.argmin(dist)) != i or dist[i] > size / 2)
    if all(b.visible for b in blocks):
        obs = Observation(blocks, (0.0, 0.0, 2.0), 0.08, size)  # the hand open, far above: nothing held
        perceived = interpret(obs, CAMERA_TOLERANCES)
        right = perceived.state is not None and perceived.state.support == scene.support
        tally.states += int(right)
        if not right:
            tilts = ", ".join(f"{i}: {math.degrees(b.tilt):.1f} deg ({b.reads} reads)" for i, b in enumerate(blocks)
                              if b.tilt is not None and b.tilt > CAMERA_TOLERANCES.tilt / 2)
            tally.failures.append(f"{perceived.reason or 'another state'}; tilted over half the tolerance: {tilts}")


def measure(n: int, args: argparse.Namespace, noise: CameraNoise) -> Tally:
    """The figures of ``args.scenes`` scenes of n cubes, ``args.frames`` frames each."""
    rng = np.random.default_rng([args.seed, n])
    tally = Tally()
    cameras = perception_cameras(n)
    for _ in range(args.scenes):
        scene = marker_scene(n, args.max_height, rng)
        try:
            for frame in range(args.frames):
                perceive_frame(scene, cameras, noise, rng, tally, check_ids=frame == 0)
        finally:
            scene.client.close()
    return tally


def row(n: int, t: Tally) -> str:
    """The markdown row of one size."""
    err = np.array(t.errors) if t.errors else np.zeros(1)
    return (f"| {n} | {t.frames} | {t.reads / t.frames:.1f} | {t.wrong_reads} ({t.wrong_retry}) "
            f"| {err.mean():.1f} | {err.max():.1f} "
            f"| {t.misidentified} | {t.unseen} ({t.unseen / t.frames:.2f} per frame) | {t.states} / {t.frames} "
            f"| {t.seconds / t.frames:.2f} |")


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    """The command line (bad values: one line, exit 2)."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", default="10,20,30", help="cube counts, comma-separated (2..50)")
    p.add_argument("--scenes", type=int, default=5, help="scenes per size (>= 1)")
    p.add_argument("--frames", type=int, default=2, help="perceptions per scene (>= 1)")
    p.add_argument("--max-height", type=int, default=8, help="tallest tower of a scene (>= 1)")
    p.add_argument("--noise", default="1.5,4", help="DEPTH_MM,COLOUR_LEVELS of sensor noise")
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args(argv)
    try:
        args.sizes = [int(s) for s in args.sizes.split(",")]
        depth, colour = (float(v) for v in args.noise.split(","))
    except ValueError:
        raise CsqlError(f"--sizes takes integers and --noise DEPTH_MM,COLOUR_LEVELS, got {args.sizes!r}, "
                        f"{args.noise!r}") from None
    if not all(2 <= s <= 50 for s in args.sizes) or min(args.scenes, args.frames, args.max_height) < 1:
        raise CsqlError("sizes must be 2..50, and --scenes, --frames and --max-height at least 1")
    if max(args.sizes) > args.max_height * len(spots()):
        raise CsqlError(f"{max(args.sizes)} cubes do not fit on {len(spots())} spots of {args.max_height}")
    args.noise = CameraNoise(depth / 1000.0, colour)
    return args


def main(argv: list[str] | None = None) -> int:
    try:
        args = parse_args(argv)
    except CsqlError as exc:
        print(f"perception_markers: {exc}", file=sys.stderr)
        return 2
    cams = perception_cameras(max(args.sizes))
    print(f"{args.scenes} scenes x {args.frames} frames per size, seed {args.seed}, towers up to {args.max_height}, "
          f"noise {args.noise.depth * 1000:g} mm / {args.noise.colour:g} levels, {len(cams)} views "
          f"{cams[0].width}x{cams[0].height}")
    print("| cubes | frames | reads / frame | wrong-id reads (second decoding) | pose error mean (mm) | max (mm) "
          "| misidentified | unseen | state read | CPU s / frame |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    failures = []
    for n in args.sizes:
        tally = measure(n, args, args.noise)
        print(row(n, tally), flush=True)
        failures += [f"{n} cubes: {reason}" for reason in tally.failures]
    for line in failures:
        print(f"state not read, {line}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
