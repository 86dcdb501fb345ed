"""Video: recording an episode's poses and drawing them into a video file.

:mod:`.recording` keeps the poses of every frame (cubes, joints, the Panda's links),
:mod:`.replay` puts them back into a scene, :mod:`.renderer` chooses the renderer (the flat
painter, TinyRenderer or EGL), :mod:`.painter` is the flat painter (Pillow, no physics client),
:mod:`.framing` chooses the cameras that show the start and the goal, :mod:`.frames` draws the
labelled, captioned frames, :mod:`.writing` runs it in workers with the shared
:class:`~csql_sim.sim.video.writing.VideoOptions`, :mod:`.encoders` writes MP4 or GIF.

Contract: imports :mod:`csql_sim.sim.perception` (the cameras), :mod:`csql_sim.sim.world`,
``core`` and ``infra``; never the control loop. Outside ``sim``, import these names from this package.
"""

from csql_sim.sim.video.recording import Recording
from csql_sim.sim.video.renderer import resolve_renderer
from csql_sim.sim.video.writing import VideoOptions, check_video_options, video_frame_count, write_video

__all__ = [
    "Recording", "VideoOptions", "check_video_options", "resolve_renderer", "video_frame_count",
    "write_video",
]
