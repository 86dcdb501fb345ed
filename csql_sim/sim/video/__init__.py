"""Video: recording an episode's poses, replaying them and rendering them to a video file.

:mod:`.recording` keeps the poses of every frame, :mod:`.replay` puts them back into a scene,
:mod:`.renderer` chooses the renderer (TinyRenderer or EGL), :mod:`.writing` renders and
captions the frames in workers (with the legend of :mod:`csql_sim.sim.world.legend`),
:mod:`.encoders` writes MP4 or GIF.

Contract: imports :mod:`csql_sim.sim.perception` (the cameras), :mod:`csql_sim.sim.world`,
``core`` and ``infra``; never the control loop. Outside ``sim``, import these names from this package.
"""

from csql_sim.sim.video.recording import Recording
from csql_sim.sim.video.renderer import resolve_renderer
from csql_sim.sim.video.writing import check_video_options, video_frame_count, write_video

__all__ = [
    "Recording", "check_video_options", "resolve_renderer", "video_frame_count",
    "write_video",
]
