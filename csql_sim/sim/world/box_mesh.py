"""The triangle mesh of a box whose six faces each show a whole texture (a cube's printed markers)."""

from __future__ import annotations

import numpy as np

Vec3 = tuple[float, float, float]


def box_mesh(half_extents: Vec3) -> tuple[list[Vec3], list[Vec3], list[tuple[float, float]], list[int]]:
    """Vertices, normals, uvs and triangle indices of a box whose every face maps the whole texture.

    Seen from outside, each face has u along one edge and v along the next (right-handed with the
    outward normal), so a marker printed on the texture reads unmirrored on all six faces.
    """
    half, eye = np.asarray(half_extents, dtype=float), np.eye(3)
    vertices, normals, uvs, indices = [], [], [], []
    for axis in range(3):
        for n in (eye[axis], -eye[axis]):
            a = eye[(axis + 1) % 3]
            b = np.cross(n, a)
            indices += [len(vertices) + k for k in (0, 1, 2, 0, 2, 3)]
            for u, v in ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)):
                vertices.append(tuple(float(c) for c in half * (n + (2 * u - 1) * a + (2 * v - 1) * b)))
                normals.append(tuple(float(c) for c in n))
                uvs.append((u, v))
    return vertices, normals, uvs, indices
