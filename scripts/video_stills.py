"""Three stills of a video: its first frame, its middle one and its last one, as PNG files.

    python scripts/video_stills.py docs/ten_cubes.mp4 docs/ten_cubes

writes ``docs/ten_cubes_start.png``, ``docs/ten_cubes_middle.png`` and ``docs/ten_cubes_end.png``
(the last frame is the end state the video holds). Bad input is one line on stderr and exit
status 2; the PNGs are written atomically.
"""

from __future__ import annotations

import argparse
import io
import sys

import imageio.v2 as imageio
from PIL import Image

from csql_sim.infra.files import write_atomic


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("video", help="an .mp4 or .gif written by csql-sim")
    parser.add_argument("prefix", help="the stills are PREFIX_start.png, PREFIX_middle.png, PREFIX_end.png")
    args = parser.parse_args()
    try:
        frames = imageio.mimread(args.video, memtest=False)
    except (OSError, ValueError, RuntimeError) as exc:
        print(f"video_stills: cannot read {args.video!r} ({str(exc).splitlines()[0] if str(exc) else exc})",
              file=sys.stderr)
        return 2
    if not frames:
        print(f"video_stills: {args.video!r} has no frames", file=sys.stderr)
        return 2
    for name, k in (("start", 0), ("middle", len(frames) // 2), ("end", len(frames) - 1)):
        buf = io.BytesIO()
        Image.fromarray(frames[k][..., :3]).save(buf, format="PNG", optimize=True)
        path = write_atomic(f"{args.prefix}_{name}.png", buf.getvalue())
        print(f"wrote {path} (frame {k + 1} of {len(frames)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
