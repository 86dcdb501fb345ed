import numpy as np

from csql_sim.sim.perception.fiducials import MarkerRead, face_pixels, marker_edge, plausible, read_markers
from csql_sim.sim.world.config import COLOURS
from csql_sim.sim.world.markers import MARKER_LAYOUT, marker_image

SIZE = 0.04


def _square(side):
    return np.array([[0.0, 0.0, 0.0], [side, 0.0, 0.0], [side, side, 0.0], [0.0, side, 0.0]])


def test_a_read_is_plausible_only_at_the_printed_size():
    side = SIZE * MARKER_LAYOUT.marker_fraction * 0.8  # the corners pulled in by ReadLimits.shrink
    assert plausible(_square(side), SIZE)
    assert not plausible(_square(2 * side), SIZE)  # a marker-like patch twice as large is no cube's
    assert not plausible(_square(0.5 * side), SIZE)


def test_ids_past_the_scene_are_ignored():
    image = np.pad(marker_image(12, COLOURS[2]), ((20, 20), (20, 20), (0, 0)), constant_values=255)
    assert [r.cube for r in read_markers(image, 13)] == [12]
    assert read_markers(image, 12) == []


def test_face_pixels_fill_the_grown_quadrilateral():
    read = MarkerRead(0, np.array([[40.0, 40.0], [60.0, 40.0], [60.0, 60.0], [40.0, 60.0]]))
    rows, cols = face_pixels(read, (100, 100))
    assert abs(len(rows) - (20 * 1.3) ** 2) < 0.15 * (20 * 1.3) ** 2
    assert rows.min() >= 36 and rows.max() <= 64 and cols.min() >= 36 and cols.max() <= 64


def test_the_marker_edge_lies_in_the_face_along_the_markers_side():
    turn = np.radians(20.0)
    a = np.array([np.cos(turn), np.sin(turn), 0.0])
    b = np.array([-np.sin(turn), np.cos(turn), 0.0])
    corners = np.array([0.01 * (u * a + v * b) for u, v in ((-1, -1), (1, -1), (1, 1), (-1, 1))])
    origins = np.tile([0.0, 0.0, 1.0], (4, 1))
    directions = corners - origins
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    edge = marker_edge(MarkerRead(0, np.zeros((4, 2))), origins, directions, np.array([0.0, 0.0, 1.0]), 0.0)
    assert edge is not None and abs(abs(edge @ a) - 1.0) < 1e-9
