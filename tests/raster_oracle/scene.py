"""The canonical scene of ``shared/bench/SCENE.md``, for the reference renderer and the ray caster."""

from __future__ import annotations

import numpy as np

from raster_oracle.camera import Camera
from raster_oracle.lights import Attenuation, Directional, Point
from raster_oracle.raster import Material

KD = (0.8, 0.3, 0.2)
KS = (0.5, 0.5, 0.5)
SHININESS = 32.0
AMBIENT = 0.05


def camera() -> Camera:
    """Eye (0, 0, 3) looking at the origin, +y up, 45 degrees vertical, near 0.1, far 100."""
    return Camera.perspective((0, 0, 3), (0, 0, 0), (0, 1, 0), fovy=45.0, near=0.1, far=100.0)


def lights() -> list[object]:
    """A white directional light travelling along (-1, -1, -1) and a point light of intensity 10 at
    (2, 2, 2) with inverse-square falloff."""
    return [
        Directional(direction=(-1.0, -1.0, -1.0), color=1.0),
        Point(position=(2.0, 2.0, 2.0), intensity=10.0, attenuation=Attenuation("inverse_square")),
    ]


def material() -> Material:
    """Classic Blinn-Phong (``blinn_phong_classic``, SCENE.md's formula) with ambient ``a kd``, Ia = 1."""
    return Material(
        "blinn_phong_classic",
        {"kd": KD, "ks": KS, "shininess": SHININESS},
        ambient=AMBIENT * np.asarray(KD),
        emission=0.0,
    )
