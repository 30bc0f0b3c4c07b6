"""The ideal sphere of SCENE.md ray cast analytically: exact hit points and exact normals (N = P on
the unit sphere), for the "Expected agreement" check of the canonical scene."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from raster_oracle.camera import Camera
from raster_oracle.raster import Material, illuminate

F64 = NDArray[np.float64]


def sphere(
    camera: Camera,
    width: int,
    height: int,
    material: Material,
    lights: list[Any],
    ambient_light: ArrayLike = 1.0,
    center: ArrayLike = (0.0, 0.0, 0.0),
    radius: float = 1.0,
) -> tuple[F64, NDArray[np.bool_]]:
    """(H, W, 3) linear colour (0 off the sphere) and the (H, W) coverage mask of a sphere, sampled at the
    pixel centres. The nearer root of ``|o + t d - c|^2 = r^2`` is taken."""
    o, d = camera.ray(width, height)
    c = np.asarray(center, dtype=np.float64)
    oc = o - c
    b = np.sum(oc * d, axis=-1)
    disc = b * b - (np.sum(oc * oc, axis=-1) - radius * radius)
    hit = disc >= 0
    t = -b - np.sqrt(np.where(hit, disc, 0.0))
    hit &= t > 0
    p = o[hit] + t[hit, None] * d[hit]
    n = (p - c) / radius
    out = np.zeros((height, width, 3))
    out[hit] = illuminate(material, p, n, camera, lights, ambient_light)
    return out, hit
