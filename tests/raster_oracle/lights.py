"""Light sources (seed 002 "Light Sources in Real-Time", seed 004 "The Phong Illumination Model (11)"):
what arrives at surface points ``p`` (N, 3) from one light, as a unit direction ``l`` toward the light
and an irradiance ``E`` per RGB channel (the renderer adds ``E * shade(l, v, n)``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]


def _rgb(x: ArrayLike) -> F64:
    a = np.asarray(x, dtype=np.float64).reshape(-1)
    return np.repeat(a, 3) if a.size == 1 else a.reshape(3)


@dataclass
class Attenuation:
    """``kind``: "none" (factor 1), "inverse_square" (``1/d^2``, radiometry) or "polynomial"
    (``1/(c1 + c2 d + c3 d^2)``, seed 004's distance factor f(d), no clamp to 1)."""

    kind: str = "inverse_square"
    c: tuple[float, float, float] = (1.0, 0.0, 0.0)

    def factor(self, d: F64) -> F64:
        if self.kind == "none":
            return np.ones_like(d)
        if self.kind == "inverse_square":
            return 1.0 / (d * d)
        c1, c2, c3 = self.c
        return 1.0 / (c1 + c2 * d + c3 * d * d)


@dataclass
class Directional:
    """Light travelling along ``direction``: ``l = -normalize(direction)``, ``E = color`` everywhere."""

    direction: ArrayLike
    color: ArrayLike = 1.0

    def incident(self, p: F64) -> tuple[F64, F64, F64]:
        d = np.asarray(self.direction, dtype=np.float64)
        l = np.broadcast_to(-d / np.linalg.norm(d), p.shape).copy()
        e = np.broadcast_to(_rgb(self.color), p.shape).copy()
        return l, e, np.full(len(p), np.inf)


@dataclass
class Point:
    """Light at ``position``: ``l = (p_l - p)/d``, ``E = I att(d)``."""

    position: ArrayLike
    intensity: ArrayLike = 1.0
    attenuation: Attenuation = field(default_factory=Attenuation)

    def incident(self, p: F64) -> tuple[F64, F64, F64]:
        to = np.asarray(self.position, dtype=np.float64) - p
        d = np.linalg.norm(to, axis=-1)
        l = to / d[:, None]
        return l, self.attenuation.factor(d)[:, None] * _rgb(self.intensity), d


def smoothstep(t: F64) -> F64:
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3 - 2 * t)


@dataclass
class Spot:
    """A point light restricted to a cone around ``direction`` (where it shines): full intensity within
    ``inner`` radians of the axis, none beyond ``outer``, ``smoothstep`` of
    ``(cos a - cos outer)/(cos inner - cos outer)`` between (Real-Time Rendering 4th ed. 5.2.2; the
    convention documented for brdfpy's spot light). ``inner == outer`` is a hard edge."""

    position: ArrayLike
    direction: ArrayLike
    intensity: ArrayLike = 1.0
    inner: float = 0.3
    outer: float = 0.5
    attenuation: Attenuation = field(default_factory=Attenuation)

    def incident(self, p: F64) -> tuple[F64, F64, F64]:
        l, e, d = Point(self.position, self.intensity, self.attenuation).incident(p)
        axis = np.asarray(self.direction, dtype=np.float64)
        cos_a = -(l @ (axis / np.linalg.norm(axis)))
        ci, co = np.cos(self.inner), np.cos(self.outer)
        if ci > co:
            cone = smoothstep((cos_a - co) / (ci - co))
        else:
            cone = (cos_a >= co).astype(np.float64)
        return l, e * cone[:, None], d
