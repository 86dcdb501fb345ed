"""The box mesh: six faces, each outward, each showing the whole texture unmirrored."""

import numpy as np

from csql_sim.sim.world.box_mesh import box_mesh


def test_every_face_is_outward_and_reads_unmirrored() -> None:
    half = (0.02, 0.03, 0.04)
    vertices, normals, uvs, indices = box_mesh(half)
    assert len(vertices) == len(normals) == len(uvs) == 24 and len(indices) == 36
    corners = {tuple(round(abs(c), 9) for c in v) for v in vertices}
    assert corners == {half}
    faces = set()
    for f in range(6):
        quad = np.array(vertices[4 * f:4 * f + 4])
        n = np.array(normals[4 * f])
        uv = np.array(uvs[4 * f:4 * f + 4])
        assert np.allclose(quad @ n, np.abs(n) @ half)  # the face lies on the box's outer side
        assert sorted(map(tuple, uv)) == [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0)]
        du, dv = quad[1] - quad[0], quad[3] - quad[0]  # u from corner 0 to 1, v from 0 to 3
        assert np.cross(du, dv) @ n > 0  # right-handed with the outward normal: not mirrored
        tri = np.array(vertices)[indices[6 * f:6 * f + 3]]
        assert np.cross(tri[1] - tri[0], tri[2] - tri[0]) @ n > 0  # wound counter-clockwise from outside
        faces.add(tuple(n))
    assert len(faces) == 6
