import numpy as np

from csql_sim.sim.perception.face_reads import FaceRead, cube_centre, cube_frame, fit_plane

SIZE = 0.04


def _face(normal, edge, centre, rng, k=200):
    """A read of the face of a cube centred at ``centre``, with the given outward normal and edge."""
    normal, edge = np.asarray(normal, float), np.asarray(edge, float)
    other = np.cross(normal, edge)
    uv = rng.uniform(-0.015, 0.015, (k, 2))
    points = centre + SIZE / 2 * normal + uv[:, :1] * edge + uv[:, 1:] * other
    return FaceRead(0, points, normal, float(normal @ (centre + SIZE / 2 * normal)), edge)


def test_two_faces_give_the_cubes_frame_and_centre():
    rng = np.random.default_rng(0)
    turn = np.radians(30.0)
    x, y, z = np.array([np.cos(turn), np.sin(turn), 0.0]), np.array([-np.sin(turn), np.cos(turn), 0.0]), np.eye(3)[2]
    centre = np.array([0.5, 0.1, 0.06])
    faces = [_face(z, x, centre, rng), _face(-y, z, centre, rng)]  # the top face, and a side face read sideways
    axes = cube_frame(faces)
    for truth in (x, y, z):
        assert max(abs(axes @ truth)) > 1 - 1e-9
    found = cube_centre(faces, axes, SIZE)
    assert abs((found - centre) @ z) < 1e-9 and abs((found - centre) @ y) < 1e-9  # pinned by the two faces
    assert abs((found - centre) @ x) < 2e-3  # no face pins x: the points' centroid


def test_one_face_places_the_centre_half_a_cube_behind_it():
    rng = np.random.default_rng(1)
    centre = np.array([0.4, -0.2, 0.02])
    face = _face(np.eye(3)[0], np.eye(3)[2], centre, rng)
    axes = cube_frame([face])
    assert np.allclose(cube_centre([face], axes, SIZE), centre, atol=1e-3)  # in-plane: the points' centroid


def test_a_plane_fit_drops_points_off_the_face():
    rng = np.random.default_rng(2)
    points = np.column_stack([rng.uniform(0, 0.03, 300), rng.uniform(0, 0.03, 300), np.zeros(300)])
    points[:10, 2] = 0.5  # the table far behind the face's edge
    normal, offset, keep = fit_plane(points, 0.0)
    assert abs(abs(normal[2]) - 1.0) < 1e-9 and abs(offset) < 1e-9 and not keep[:10].any() and keep[10:].all()
