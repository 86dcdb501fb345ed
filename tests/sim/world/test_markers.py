import math

import numpy as np
import pytest

from csql_sim.infra.errors import CsqlError
from csql_sim.sim.perception.camera import Camera
from csql_sim.sim.perception.fiducials import read_markers
from csql_sim.sim.world.client import PhysicsClient
from csql_sim.sim.world.config import COLOURS, DEFAULT_CONFIG
from csql_sim.sim.world.markers import (
    DICTIONARY_SIZE,
    MARKER_LAYOUT,
    PRINTED,
    apply_markers,
    marker_id,
    marker_image,
    marker_texture,
)


def test_every_printed_face_reads_as_its_cubes_id():
    for i in range(30):
        image = marker_image(i, COLOURS[i % len(COLOURS)])
        framed = np.pad(image, ((20, 20), (20, 20), (0, 0)), constant_values=255)
        assert [r.cube for r in read_markers(framed, DICTIONARY_SIZE)] == [i]


def test_the_texture_is_a_frame_of_paint_round_a_quiet_zone_and_the_marker():
    image = marker_image(3, COLOURS[3])
    px = MARKER_LAYOUT.cell_pixels
    assert image.shape == (round(MARKER_LAYOUT.face_cells * px),) * 2 + (3,)
    assert (image[0, 0] == [round(255 * c) for c in COLOURS[3][:3]]).all()  # the paint at the edge
    assert (image[px, px] == 255).all()  # white quiet zone inside the frame
    start = round((MARKER_LAYOUT.frame + MARKER_LAYOUT.quiet) * px)
    assert (image[start + 2, start + 2] == 0).all()  # the marker's black border


def test_a_cube_past_the_dictionary_has_no_marker():
    assert marker_id(DICTIONARY_SIZE - 1) == DICTIONARY_SIZE - 1
    with pytest.raises(CsqlError):
        marker_id(DICTIONARY_SIZE)


def test_the_texture_file_is_written_once_and_read_back():
    path = marker_texture(7, COLOURS[7])
    assert path.exists() and marker_texture(7, COLOURS[7]) == path
    assert path.stat().st_size > 0


@pytest.mark.parametrize("face", ["+x", "-x", "+y", "-y", "+z", "-z"])
def test_every_face_of_a_marked_cube_shows_its_marker(face):
    """The box mesh maps the whole texture to each face: seen head-on, each face reads as the cube's id."""
    axis, sign = "xyz".index(face[1]), 1.0 if face[0] == "+" else -1.0
    eye = [0.0, 0.0, 0.0]
    eye[axis] = 0.25 * sign
    up = (0.0, 0.0, 1.0) if axis != 2 else (1.0, 0.0, 0.0)
    camera = Camera(eye=tuple(eye), target=(0.0, 0.0, 0.0), up=up, fov=30.0, width=160, height=160)
    with PhysicsClient(DEFAULT_CONFIG.physics) as client:
        half = DEFAULT_CONFIG.physics.cube_size / 2
        bodies = [client.add_box((half,) * 3, 0.0, PRINTED, (0.0, 0.0, 0.0), True) for _ in range(5)]
        for k, body in enumerate(bodies[:4]):  # decoys far away: only the last cube is in view
            client.set_body_pose(body, (5.0 + k, 5.0, 0.0), (0.0, 0.0, 0.0, 1.0))
        apply_markers(client, bodies, COLOURS)
        rgb, _, _ = client.render(*camera.matrices(), camera.width, camera.height)
        reads = read_markers(rgb, 5)
    assert [r.cube for r in reads] == [4]
    side = np.linalg.norm(reads[0].corners[1] - reads[0].corners[0])
    focal = camera.height / 2 / math.tan(math.radians(camera.fov / 2))
    expected = focal * 2 * half * MARKER_LAYOUT.marker_fraction / (0.25 - half)
    assert abs(side - expected) < 0.1 * expected  # the marker fills the face as printed, not a few texels of it
