"""Light sources for scenes (seed 002, SPEC rows 14–15): directional, point and spot lights.

Each light answers, at a surface point, from which direction ``l`` light arrives and with which
irradiance ``E``; a render adds ``E · model.shade(l, v, n)`` per light. Colors are linear RGB (a number
means gray). Angles are in **degrees**.

Attenuation of point and spot lights (``attenuation=``):

- ``"inverse_square"`` (default): ``E = I / d²``, the physical law (``I`` a radiant intensity);
- ``"none"``: ``E = I`` at any distance;
- ``(c1, c2, c3)``: the Phong model's distance factor ``E = I / (c1 + c2·d + c3·d²)`` (seed 004).
"""

from __future__ import annotations

import math
from typing import Any, Union

import numpy as np
from numpy.typing import ArrayLike

from brdfpy import _brdfpy
from brdfpy.camera import vec3

__all__ = ["Attenuation", "DirectionalLight", "Light", "PointLight", "SpotLight", "color3"]

#: ``"inverse_square"``, ``"none"`` or polynomial coefficients ``(c1, c2, c3)``.
Attenuation = Union[str, tuple[float, float, float], None]


def color3(name: str, x: Any) -> tuple[float, float, float]:
    """A linear RGB color from one number (gray) or three, finite and ≥ 0."""
    if isinstance(x, bool):
        raise TypeError(f"{name}: expected a number or three numbers, got bool")
    if isinstance(x, (int, float, np.integer, np.floating)):
        c = (float(x),) * 3
    else:
        c = vec3(name, x)
    if not all(math.isfinite(v) and v >= 0 for v in c):
        raise ValueError(f"{name}: must be finite and >= 0 in every channel, got {list(c)}")
    return (c[0], c[1], c[2])


def _attenuation(x: Any) -> str | tuple[float, float, float]:
    if x is None:
        return "none"
    if isinstance(x, str):
        low = x.lower()
        if low not in ("none", "inverse_square"):
            raise ValueError(f"attenuation: expected 'none', 'inverse_square' or (c1, c2, c3), got {x!r}")
        return low
    c = vec3("attenuation", x)
    if min(c) < 0 or sum(c) <= 0:
        raise ValueError(f"attenuation: coefficients must be >= 0 and not all zero, got {list(c)}")
    return c


class Light:
    """Base class of the lights; see :class:`DirectionalLight`, :class:`PointLight`, :class:`SpotLight`."""

    __slots__ = ("_l",)

    _l: _brdfpy.RasterLight

    def incident(
        self, p: ArrayLike
    ) -> tuple[tuple[float, float, float], tuple[float, float, float], float] | None:
        """What arrives at point ``p``: ``(l, irradiance, distance)`` with ``l`` the unit direction toward
        the light, or ``None`` (outside a spot's cone, or at the light's position)."""
        r = self._l.incident(vec3("p", p))
        if r is None:
            return None
        l, e, d = r
        return (tuple(l), tuple(e), d)  # type: ignore[return-value]

    def _fields(self) -> dict[str, Any]:
        return dict(self._l.fields())

    def __repr__(self) -> str:
        f = self._fields()
        f.pop("kind")
        for k in ("inner_angle", "outer_angle"):
            if k in f:
                f[k] = round(math.degrees(f[k]), 4)
        args = ", ".join(
            f"{k}={tuple(round(x, 6) for x in v) if isinstance(v, (list, tuple)) else v!r}"
            for k, v in f.items()
        )
        return f"brdfpy.{type(self).__name__}({args})"


class DirectionalLight(Light):
    """Light from one direction everywhere, like the sun.

    Parameters
    ----------
    direction : three numbers
        The direction in which the light **travels** (from the light into the scene; normalised here).
        The default ``(-1, -1, -1)`` comes from the upper right front.
    color : number or three numbers
        Irradiance on a surface facing the light (linear RGB).
    """

    __slots__ = ()

    def __init__(self, direction: ArrayLike = (-1.0, -1.0, -1.0), color: Any = 1.0) -> None:
        self._l = _brdfpy.RasterLight.directional(vec3("direction", direction), color3("color", color))

    @property
    def direction(self) -> tuple[float, float, float]:
        """Unit direction of travel."""
        return tuple(self._fields()["direction"])

    @property
    def color(self) -> tuple[float, float, float]:
        """Irradiance (linear RGB)."""
        return tuple(self._fields()["color"])


class PointLight(Light):
    """An infinitely small light at ``position`` radiating ``intensity`` in every direction.

    Parameters
    ----------
    position : three numbers
    intensity : number or three numbers
        Radiant intensity (linear RGB); with the default inverse-square attenuation a surface at distance
        ``d`` facing the light receives ``intensity / d²``.
    attenuation : "inverse_square", "none" or (c1, c2, c3)
        See the module documentation.
    """

    __slots__ = ()

    def __init__(
        self, position: ArrayLike, intensity: Any = 1.0, attenuation: Attenuation = "inverse_square"
    ) -> None:
        self._l = _brdfpy.RasterLight.point(
            vec3("position", position), color3("intensity", intensity), _attenuation(attenuation)
        )

    @property
    def position(self) -> tuple[float, float, float]:
        """Position of the light."""
        return tuple(self._fields()["position"])

    @property
    def intensity(self) -> tuple[float, float, float]:
        """Radiant intensity (linear RGB)."""
        return tuple(self._fields()["intensity"])


class SpotLight(Light):
    """A point light restricted to a cone around ``direction``.

    Full intensity within ``inner_angle`` of the axis, nothing beyond ``outer_angle``, and a smooth
    (smoothstep in the cosine) falloff in between.

    Parameters
    ----------
    position : three numbers
    direction : three numbers
        Axis of the cone: where the spot points (normalised here).
    intensity : number or three numbers
        Radiant intensity on the axis (linear RGB).
    inner_angle, outer_angle : float
        Half-angles of the cone in **degrees**, ``0 <= inner_angle <= outer_angle < 180``.
    attenuation : "inverse_square", "none" or (c1, c2, c3)
    """

    __slots__ = ()

    def __init__(
        self,
        position: ArrayLike,
        direction: ArrayLike,
        intensity: Any = 1.0,
        inner_angle: float = 20.0,
        outer_angle: float = 30.0,
        attenuation: Attenuation = "inverse_square",
    ) -> None:
        angles = []
        for name, a in (("inner_angle", inner_angle), ("outer_angle", outer_angle)):
            if isinstance(a, bool) or not isinstance(a, (int, float, np.integer, np.floating)):
                raise TypeError(f"{name}: expected a number of degrees, got {type(a).__name__}")
            angles.append(float(a))
        if not (0.0 < angles[1] < 180.0) or not math.isfinite(angles[1]):
            raise ValueError(f"outer_angle: must lie in (0, 180) degrees, got {angles[1]}")
        if not (0.0 <= angles[0] <= angles[1]):
            raise ValueError(
                f"inner_angle: must lie in [0, outer_angle = {angles[1]}] degrees, got {angles[0]}"
            )
        angles = [math.radians(a) for a in angles]
        self._l = _brdfpy.RasterLight.spot(
            vec3("position", position),
            vec3("direction", direction),
            color3("intensity", intensity),
            angles[0],
            angles[1],
            _attenuation(attenuation),
        )
