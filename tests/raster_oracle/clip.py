"""Homogeneous clipping before the perspective divide (Sutherland & Hodgman 1974; Blinn & Newell 1978
"Clipping using homogeneous coordinates").

OpenGL's view volume in clip space is ``-w <= x, y, z <= w``. Only the near (``z + w >= 0``) and far
(``w - z >= 0``) planes are clipped here: the near plane because behind it ``w`` goes to 0 and changes
sign (the divide would be meaningless), the far plane because OpenGL drops what lies beyond it. The side
planes need no clipping in a reference: the rasterizer only visits pixels inside the image, and float64
edge functions of a triangle reaching far off screen are exact enough. Attributes are linear in clip
space (clip space is an affine image of world space), so a new vertex gets the same ``t`` for its
position and for its attributes.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

F64 = NDArray[np.float64]

#: (a, b) with the plane ``a.(x, y, z, w) >= 0`` inside.
PLANES = (np.array([0.0, 0.0, 1.0, 1.0]), np.array([0.0, 0.0, -1.0, 1.0]))


def clip_polygon(pos: F64, attr: F64) -> tuple[F64, F64]:
    """Clip a convex polygon (k, 4) in clip space with per-vertex attributes (k, m) against the near and
    far planes. Returns the clipped polygon (possibly empty)."""
    for plane in PLANES:
        if len(pos) == 0:
            break
        d = pos @ plane
        if np.all(d >= 0):
            continue
        out_p, out_a = [], []
        k = len(pos)
        for i in range(k):
            j = (i + 1) % k
            if d[i] >= 0:
                out_p.append(pos[i])
                out_a.append(attr[i])
            if (d[i] >= 0) != (d[j] >= 0):
                t = d[i] / (d[i] - d[j])
                out_p.append(pos[i] + t * (pos[j] - pos[i]))
                out_a.append(attr[i] + t * (attr[j] - attr[i]))
        pos = np.array(out_p).reshape(-1, 4)
        attr = np.array(out_a).reshape(-1, attr.shape[1])
    return pos, attr


def clip_triangle(pos: F64, attr: F64) -> list[tuple[F64, F64]]:
    """Clip a triangle and fan-triangulate the result: a list of 0, 1 or more (3, 4), (3, m) triangles."""
    if np.all(pos @ PLANES[0] >= 0) and np.all(pos @ PLANES[1] >= 0):
        return [(pos, attr)]
    p, a = clip_polygon(pos, attr)
    return [(p[[0, i, i + 1]], a[[0, i, i + 1]]) for i in range(1, len(p) - 1)]
