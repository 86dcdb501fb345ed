"""ArUco against AprilTag on the cubes: reads per image by camera resolution, at 30 cubes.

Regenerates docs/results/arm.md (the table "Marker families").

The scenes are :func:`perception_markers.marker_scene`'s (30 cubes in towers up to 8, the
Panda at home), each cube's faces printed with its marker of one family in the same layout
as :mod:`csql_sim.sim.world.markers` (paint frame, quiet zone, marker). Each family is read by
its own usual detector: ArUco ``DICT_4X4_50`` by OpenCV's (``csql_sim``'s reader), the
AprilTag families ``tag16h5`` and ``tag36h11`` by ``pupil-apriltags`` (the AprilTag 3
library; OpenCV draws their images, in the same bit layout). The three perception views
are rendered at each resolution, with sensor noise; a read counts if its id is the cube the
renderer drew under its centre, and is wrong otherwise.

    pip install pupil-apriltags          # the comparison only; csql-sim does not need it
    python benchmarks/perception_marker_families.py                      # 3 scenes, 640x480 .. 1280x960
    python benchmarks/perception_marker_families.py --scenes 5 --seed 1
    python benchmarks/perception_marker_families.py --family "apriltag tag36h11"   # one family

Bad input is one line on stderr and exit status 2.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from dataclasses import replace
from functools import cache
from pathlib import Path

import cv2
import numpy as np
from perception_markers import marker_scene

from csql_sim.sim.perception.camera import perception_cameras
from csql_sim.sim.perception.fiducials import read_markers
from csql_sim.sim.perception.rgbd import CameraNoise, add_noise
from csql_sim.sim.world.config import COLOURS
from csql_sim.sim.world.markers import MARKER_LAYOUT

N = 30
FAMILIES = {"aruco 4x4_50": cv2.aruco.DICT_4X4_50, "apriltag tag16h5": cv2.aruco.DICT_APRILTAG_16h5,
            "apriltag tag36h11": cv2.aruco.DICT_APRILTAG_36h11}
RESOLUTIONS = ((640, 480), (960, 720), (1280, 960))


def face_image(family: str, i: int, face_px: int = 160) -> np.ndarray:
    """Cube i's face in ``family``: paint frame, quiet zone and marker in the markers module's proportions."""
    marker = round(face_px * MARKER_LAYOUT.marker_fraction)
    frame = round(face_px * MARKER_LAYOUT.frame / MARKER_LAYOUT.face_cells)
    code = cv2.aruco.generateImageMarker(cv2.aruco.getPredefinedDictionary(FAMILIES[family]), i, marker)
    image = np.full((face_px, face_px, 3), [round(255 * c) for c in COLOURS[i % len(COLOURS)][:3]], dtype=np.uint8)
    image[frame:face_px - frame, frame:face_px - frame] = 255
    start = (face_px - marker) // 2
    image[start:start + marker, start:start + marker] = code[:, :, None]
    return image


@cache
def _apriltag_detector(name: str):  # noqa: ANN202 - a pupil_apriltags.Detector
    """The detector of one AprilTag family, kept for the life of the process.

    Here a pupil-apriltags detector freed while another lived corrupted the heap, and one
    detector of both families read no tag36h11 at all; so each family has its own, never freed
    (:func:`main` leaves by ``os._exit``).
    """
    import pupil_apriltags

    return pupil_apriltags.Detector(families=name)


def reader(family: str):  # noqa: ANN201 - a callable: RGB image -> [(id, centre xy)]
    """The family's usual detector."""
    if family.startswith("aruco"):
        return lambda rgb: [(r.cube, r.centre) for r in read_markers(rgb, N)]
    name = family.split()[-1]

    def read(rgb: np.ndarray) -> list[tuple[int, np.ndarray]]:
        found = _apriltag_detector(name).detect(cv2.cvtColor(rgb, cv2.COLOR_RGB2GRAY))
        return [(d.tag_id, np.asarray(d.center)) for d in found if _name(d.tag_family) == name]

    return read


def _name(family: bytes | str) -> str:
    return family.decode() if isinstance(family, bytes) else family


def count(family: str, args: argparse.Namespace, folder: Path) -> dict[tuple[int, int], tuple[int, int, int]]:
    """(reads, wrong reads, cubes read in some view) summed over the scenes, per resolution."""
    rng = np.random.default_rng(args.seed)
    read = reader(family)
    totals = {res: [0, 0, 0] for res in RESOLUTIONS}
    for _ in range(args.scenes):
        scene = marker_scene(N, 8, rng)
        for i, body in enumerate(scene.bodies):
            path = folder / f"{family.replace(' ', '-')}-{i}.png"
            cv2.imwrite(str(path), cv2.cvtColor(face_image(family, i), cv2.COLOR_RGB2BGR))
            scene.client.set_texture(body, scene.client.load_texture(str(path)))
        for res in RESOLUTIONS:
            seen = set()
            for camera in perception_cameras(N):
                camera = replace(camera, width=res[0], height=res[1])
                rgb, depth, ids = scene.client.render(*camera.matrices(), *res, segmentation=True)
                rgb, _ = add_noise(rgb, depth, camera, args.noise, rng)
                for cube, centre in read(rgb):
                    col, row = np.clip(np.rint(centre).astype(int), 0, [res[0] - 1, res[1] - 1])
                    right = 0 <= cube < N and ids[row, col] == scene.bodies[cube]
                    totals[res][0] += 1
                    totals[res][1] += int(not right)
                    seen |= {cube} if right else set()
            totals[res][2] += len(seen)
        scene.client.close()
    return {res: tuple(v) for res, v in totals.items()}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenes", type=int, default=3, help="30-cube scenes (>= 1)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--family", choices=sorted(FAMILIES), action="append",
                   help="the families to compare (repeatable; default all three)")
    args = p.parse_args(argv)
    if args.scenes < 1:
        print("perception_marker_families: --scenes must be at least 1", file=sys.stderr)
        return 2
    try:
        import pupil_apriltags  # noqa: F401
    except ImportError:
        print("perception_marker_families: the comparison needs pupil-apriltags (pip install pupil-apriltags)",
              file=sys.stderr)
        return 2
    args.noise = CameraNoise(0.0015, 4.0)
    print(f"{args.scenes} scenes of {N} cubes, seed {args.seed}, 3 views, noise 1.5 mm / 4 levels; "
          f"reads per image (wrong ids), cubes read in some view of {args.scenes * N}")
    print("| family | " + " | ".join(f"{w}x{h}" for w, h in RESOLUTIONS) + " |")
    print("|---|" + "---|" * len(RESOLUTIONS))
    with tempfile.TemporaryDirectory() as folder:
        for family in args.family or FAMILIES:
            totals = count(family, args, Path(folder))
            images = 3 * args.scenes
            cells = [f"{r / images:.1f} ({w}); {c} cubes" for r, w, c in (totals[res] for res in RESOLUTIONS)]
            print(f"| {family} | " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    status = main()
    sys.stdout.flush()
    os._exit(status)  # not sys.exit: freeing the AprilTag detectors at shutdown crashed here
