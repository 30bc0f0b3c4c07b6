"""Light sources for scenes: directional, point and spot lights, and sphere and rectangle area lights.

Each light answers, at a surface point, from which direction ``l`` light arrives and with which
irradiance ``E``; a render adds ``E · model.shade(l, v, n)`` per light. Angles are in **degrees**.

One convention for every light (that of glTF's ``KHR_lights_punctual`` and of three.js):

- **color** and **intensity** on every kind: ``color`` is the light's linear RGB colour (a number means gray,
  default white) and ``intensity`` its strength (a number, or three for a per-channel strength; default 1).
  The light emits ``color ∘ intensity``: for a :class:`DirectionalLight` the irradiance [W/m²] on a surface
  facing it, for a :class:`PointLight` or :class:`SpotLight` the radiant intensity [W/sr] (on the axis of a
  spot). ``PointLight(p, intensity=10)`` and ``PointLight(p, color=10)`` are the same light; say
  ``color=(1, 0.9, 0.8), intensity=10`` to keep the two apart.
- **direction** is always the direction in which the light **travels** (from the light into the scene):
  ``DirectionalLight((0, -1, 0))`` shines straight down, as does ``SpotLight(p, (0, -1, 0))``. (The
  direction *toward* the light is the ``l`` of the reflectance models, what :meth:`Light.incident` returns.)

Area lights (:class:`SphereLight`, :class:`RectLight`) have a surface emitting the constant radiance
``L = color ∘ intensity`` [W/(m²·sr)]. They give soft shadows: a render estimates the light they reflect,
``L_o = ∫ L · V(p, l) · f_r(l, v) · cos θ_l dω`` over the solid angle they subtend, by Monte Carlo with
multiple importance sampling (Veach & Guibas 1995) between the light and the material
(``Scene.render(area_samples=, area_seed=)``), with visibility ``V`` traced whatever ``shadows=`` says. A
sphere of radius ``r`` fully above a surface's horizon gives the irradiance ``E = π L sin²α cos θ``
(``sin α = r/d``, ``d`` the distance to its centre, ``θ`` the angle between the normal and the direction
to it): the irradiance of a point light of intensity ``L · π r²`` at its centre. A rectangle's
irradiance is Lambert's polygon formula ``E = L/2 · Σ_i γ_i n·û_i`` (``γ_i`` the angle edge ``i``
subtends, ``û_i`` the unit normal of the plane through the point and that edge; Baum, Rushmeier &
Winget 1989, Arvo 1995). Area lights are not geometry and the camera does not see them: to show one, add
a mesh with ``emission=`` just inside the sphere or just behind the rectangle.

Attenuation of point and spot lights (``attenuation=``):

- ``"inverse_square"`` (default): ``E = I / d²``, the physical law (``I`` a radiant intensity);
- ``"none"``: ``E = I`` at any distance;
- ``(c1, c2, c3)``: the distance factor of Phong's illumination model as given by Foley, van Dam, Feiner &
  Hughes, *Computer Graphics: Principles and Practice* (2nd ed., 1990, §16.1), ``E = I / (c1 + c2·d + c3·d²)``
  (without Foley's ``min(1, ·)``: ``c1 < 1`` brightens points near the light).
"""

from __future__ import annotations

import math
from typing import Any, Union

import numpy as np
from numpy.typing import ArrayLike

from brdfpy import _brdfpy
from brdfpy.camera import vec3

__all__ = [
    "AreaLight",
    "Attenuation",
    "DirectionalLight",
    "Light",
    "PointLight",
    "RectLight",
    "SphereLight",
    "SpotLight",
    "color3",
]

#: ``"inverse_square"``, ``"none"`` or polynomial coefficients ``(c1, c2, c3)``.
Attenuation = Union[str, tuple[float, float, float], None]

_F32_MAX = float(np.finfo(np.float32).max)


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


def _short(v: Any) -> Any:
    """A float stored as float32, rounded to 6 decimals for a repr (a radius of 0.35, not 0.3499999940)."""
    return round(v, 6) if isinstance(v, float) else v


def _emitted(color: Any, intensity: Any) -> tuple[float, float, float]:
    """``color ∘ intensity``, both checked (finite, ≥ 0), each named in an error."""
    c, k = color3("color", color), color3("intensity", intensity)
    e = (c[0] * k[0], c[1] * k[1], c[2] * k[2])
    if not all(v <= _F32_MAX for v in e):
        raise ValueError(
            f"color, intensity: their product exceeds the float32 range, got color {list(c)}, "
            f"intensity {list(k)}"
        )
    return e


class Light:
    """Base class of the lights; see :class:`DirectionalLight`, :class:`PointLight`, :class:`SpotLight`.

    Every light has a :attr:`color` and an :attr:`intensity` (see the module documentation: it emits
    ``color ∘ intensity``) and answers :meth:`incident`."""

    __slots__ = ("_color", "_intensity", "_l")

    _l: _brdfpy.RasterLight | _brdfpy.RasterAreaLight
    _color: tuple[float, float, float]
    _intensity: tuple[float, float, float]

    def __init__(self) -> None:
        raise TypeError(
            "Light: is the base class; build a DirectionalLight, PointLight, SpotLight, SphereLight or "
            "RectLight"
        )

    def _set_amount(self, color: Any, intensity: Any) -> tuple[float, float, float]:
        emitted = _emitted(color, intensity)
        self._color, self._intensity = color3("color", color), color3("intensity", intensity)
        return emitted

    @property
    def color(self) -> tuple[float, float, float]:
        """The light's colour (linear RGB), as given."""
        return self._color

    @property
    def intensity(self) -> tuple[float, float, float]:
        """The light's intensity (per channel), as given."""
        return self._intensity

    @property
    def emitted(self) -> tuple[float, float, float]:
        """``color ∘ intensity``: the irradiance [W/m²] of a directional light on a surface facing it, the
        radiant intensity [W/sr] of a point light (of a spot light on its axis), the radiance [W/(m²·sr)]
        of an area light."""
        f = self._fields()
        key = {"directional": "color", "sphere": "radiance", "rect": "radiance"}.get(f["kind"], "intensity")
        return tuple(f[key])

    def __new__(cls, *args: Any, **kwargs: Any) -> Light:
        if cls is Light or cls is AreaLight:
            raise TypeError(
                f"{cls.__name__} is the base class: create a DirectionalLight, PointLight, SpotLight, "
                "SphereLight or RectLight"
            )
        return super().__new__(cls)

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

    def __reduce__(self) -> tuple[Any, ...]:
        # The stored fields (radians, unit direction), rebuilt with the same bits, and color / intensity
        # as given (the renderer stores only their product).
        return (_rebuild_light, (type(self), self._fields(), self._color, self._intensity))

    def __repr__(self) -> str:
        f = self._fields()
        f.pop("kind")
        # The renderer's field holds color ∘ intensity; show the two as given.
        f.pop("color", None)
        f.pop("radiance", None)
        f["color"], f["intensity"] = self._color, self._intensity
        for k in ("inner_angle", "outer_angle"):
            if k in f:
                f[k] = round(math.degrees(f[k]), 4)
        args = ", ".join(
            f"{k}={tuple(round(x, 6) for x in v) if isinstance(v, (list, tuple)) else _short(v)!r}"
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
        The light's colour (linear RGB; a number means gray). Default white.
    intensity : number or three numbers
        Its strength. The irradiance on a surface facing the light is ``color ∘ intensity`` [W/m²].
    """

    __slots__ = ()

    def __init__(
        self, direction: ArrayLike = (-1.0, -1.0, -1.0), color: Any = 1.0, *, intensity: Any = 1.0
    ) -> None:
        d = vec3("direction", direction)
        self._l = _brdfpy.RasterLight.directional(d, self._set_amount(color, intensity))

    @property
    def direction(self) -> tuple[float, float, float]:
        """Unit direction of travel."""
        return tuple(self._fields()["direction"])


class PointLight(Light):
    """An infinitely small light at ``position`` radiating ``color ∘ intensity`` in every direction.

    Parameters
    ----------
    position : three numbers
    intensity : number or three numbers
        Its strength: the radiant intensity is ``color ∘ intensity`` [W/sr]; with the default
        inverse-square attenuation a surface at distance ``d`` facing the light receives that over ``d²``.
    attenuation : "inverse_square", "none" or (c1, c2, c3)
        See the module documentation.
    color : number or three numbers, keyword
        The light's colour (linear RGB; a number means gray). Default white.
    """

    __slots__ = ()

    def __init__(
        self,
        position: ArrayLike,
        intensity: Any = 1.0,
        attenuation: Attenuation = "inverse_square",
        *,
        color: Any = 1.0,
    ) -> None:
        p = vec3("position", position)
        emitted = self._set_amount(color, intensity)
        self._l = _brdfpy.RasterLight.point(p, emitted, _attenuation(attenuation))

    @property
    def position(self) -> tuple[float, float, float]:
        """Position of the light."""
        return tuple(self._fields()["position"])


class SpotLight(Light):
    """A point light restricted to a cone around ``direction``.

    Full intensity within ``inner_angle`` of the axis, nothing beyond ``outer_angle``, and a smooth
    (smoothstep in the cosine) falloff in between.

    Parameters
    ----------
    position : three numbers
    direction : three numbers
        Axis of the cone: the direction in which the light **travels** (where the spot points; normalised
        here).
    intensity : number or three numbers
        Its strength: the radiant intensity on the axis is ``color ∘ intensity`` [W/sr].
    inner_angle, outer_angle : float
        Half-angles of the cone in **degrees**, ``0 <= inner_angle <= outer_angle < 180``.
    attenuation : "inverse_square", "none" or (c1, c2, c3)
    color : number or three numbers, keyword
        The light's colour (linear RGB; a number means gray). Default white.
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
        *,
        color: Any = 1.0,
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
        p, d = vec3("position", position), vec3("direction", direction)
        self._l = _brdfpy.RasterLight.spot(
            p, d, self._set_amount(color, intensity), angles[0], angles[1], _attenuation(attenuation)
        )

    @property
    def position(self) -> tuple[float, float, float]:
        """Position of the light."""
        return tuple(self._fields()["position"])

    @property
    def direction(self) -> tuple[float, float, float]:
        """Unit direction of travel (the cone's axis)."""
        return tuple(self._fields()["direction"])


class AreaLight(Light):
    """Base class of the area lights, :class:`SphereLight` and :class:`RectLight` (see the module
    documentation): a surface emitting the radiance ``color ∘ intensity`` [W/(m²·sr)].

    :meth:`incident` gives, from the unoccluded vector irradiance ``Φ`` (Arvo 1995), ``l = Φ/|Φ|``, the
    irradiance ``|Φ|`` on a surface facing ``l`` that sees the whole light, and the distance to the light's
    centre (``None`` inside a sphere light or behind a one-sided rectangle)."""

    __slots__ = ()

    _l: _brdfpy.RasterAreaLight

    @property
    def center(self) -> tuple[float, float, float]:
        """Centre of the light."""
        return tuple(self._fields()["center"])


def _length(name: str, x: Any) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name}: expected a number, got {type(x).__name__}")
    return float(x)


class SphereLight(AreaLight):
    """A sphere of ``radius`` at ``center`` whose surface emits the radiance ``color ∘ intensity``
    [W/(m²·sr)] outward (a point inside it receives nothing).

    Seen from a point at distance ``d`` it fills a cone of half-angle ``α``, ``sin α = r/d``; a surface
    that sees all of it receives ``E = π L sin²α cos θ`` (``θ`` between the normal and the direction to
    the centre), the irradiance of a :class:`PointLight` of intensity ``L · π r²`` at the centre. Sampled
    uniformly in that cone (Shirley, Wang & Zimmerman 1996; Pharr, Jakob & Humphreys, *Physically Based
    Rendering* 4th ed., §6.2.4).

    Parameters
    ----------
    center : three numbers
    radius : float
        > 0, in scene units.
    intensity : number or three numbers
        Its strength: the radiance is ``color ∘ intensity`` [W/(m²·sr)].
    color : number or three numbers, keyword
        The light's colour (linear RGB; a number means gray). Default white.
    """

    __slots__ = ()

    def __init__(self, center: ArrayLike, radius: float, intensity: Any = 1.0, *, color: Any = 1.0) -> None:
        c, r = vec3("center", center), _length("radius", radius)
        self._l = _brdfpy.RasterAreaLight.sphere(c, r, self._set_amount(color, intensity))

    @property
    def radius(self) -> float:
        """Radius of the sphere."""
        return float(self._fields()["radius"])


class RectLight(AreaLight):
    """A rectangle with corners ``center ± edge0/2 ± edge1/2`` emitting the radiance ``color ∘ intensity``
    [W/(m²·sr)] on the side of its :attr:`normal` ``edge0 × edge1`` (on both with ``two_sided=True``).

    The edges need not be perpendicular (a parallelogram works the same); they must not be parallel.
    ``RectLight((0, 2, 0), (1, 0, 0), (0, 0, 1))`` is a 1×1 square at height 2 shining down (``x × z = −y``).
    Its points are sampled uniformly on the area, converted to solid angle (``p = t² / (A cos θ_q)``).

    Parameters
    ----------
    center : three numbers
    edge0, edge1 : three numbers
        The edge vectors (full lengths).
    intensity : number or three numbers
        Its strength: the radiance is ``color ∘ intensity`` [W/(m²·sr)].
    color : number or three numbers, keyword
        The light's colour (linear RGB; a number means gray). Default white.
    two_sided : bool, keyword
        Emit from both sides (default: only on the side of ``edge0 × edge1``).
    """

    __slots__ = ()

    def __init__(
        self,
        center: ArrayLike,
        edge0: ArrayLike,
        edge1: ArrayLike,
        intensity: Any = 1.0,
        *,
        color: Any = 1.0,
        two_sided: bool = False,
    ) -> None:
        if not isinstance(two_sided, (bool, np.bool_)):
            raise TypeError(f"two_sided: expected a bool, got {type(two_sided).__name__}")
        c, e0, e1 = vec3("center", center), vec3("edge0", edge0), vec3("edge1", edge1)
        emitted = self._set_amount(color, intensity)
        self._l = _brdfpy.RasterAreaLight.rect(c, e0, e1, emitted, bool(two_sided))

    @property
    def edge0(self) -> tuple[float, float, float]:
        """First edge vector."""
        return tuple(self._fields()["edge0"])

    @property
    def edge1(self) -> tuple[float, float, float]:
        """Second edge vector."""
        return tuple(self._fields()["edge1"])

    @property
    def two_sided(self) -> bool:
        """Whether it emits from both sides."""
        return bool(self._fields()["two_sided"])

    @property
    def normal(self) -> tuple[float, float, float]:
        """Unit normal ``edge0 × edge1 / |edge0 × edge1|``, the emitting side."""
        n = np.cross(np.asarray(self.edge0, np.float64), np.asarray(self.edge1, np.float64))
        n /= np.linalg.norm(n)
        return (float(n[0]), float(n[1]), float(n[2]))

    @property
    def area(self) -> float:
        """Area ``|edge0 × edge1|``."""
        return float(np.linalg.norm(np.cross(self.edge0, self.edge1)))


def _rebuild_light(cls: type[Light], f: dict[str, Any], color: Any = None, intensity: Any = None) -> Light:
    raw = _brdfpy.RasterLight
    kind = f["kind"]
    if kind in ("sphere", "rect"):
        area = _brdfpy.RasterAreaLight
        if kind == "sphere":
            al = area.sphere(f["center"], f["radius"], f["radiance"])
        else:
            al = area.rect(f["center"], f["edge0"], f["edge1"], f["radiance"], f["two_sided"])
        made = cls.__new__(cls)
        made._l = al
        made._color = color3("color", f["radiance"] if color is None else color)
        made._intensity = color3("intensity", 1.0 if intensity is None else intensity)
        return made
    if kind == "directional":
        l = raw.directional(f["direction"], f["color"])
    elif kind == "point":
        l = raw.point(f["position"], f["intensity"], f["attenuation"])
    else:
        angles = (f["inner_angle"], f["outer_angle"])
        l = raw.spot(f["position"], f["direction"], f["intensity"], *angles, f["attenuation"])
    if kind != "point":
        # The constructors normalise the direction; keep the stored one instead (the same bits).
        l = _brdfpy._light_with_direction(l, f["direction"])
    light = cls.__new__(cls)
    light._l = l
    emitted = f["color"] if kind == "directional" else f["intensity"]
    # A pickle without the two as given (older brdfpy) reads as colour = what is emitted, intensity 1.
    light._color = color3("color", emitted if color is None else color)
    light._intensity = color3("intensity", 1.0 if intensity is None else intensity)
    return light
