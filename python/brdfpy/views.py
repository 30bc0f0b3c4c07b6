"""The views of a reflectance model that Disney's BRDF Explorer draws, as data (no plotting dependency).

Burley's BRDF Explorer (Burley 2012, "Physically-Based Shading at Disney", §3) looks at a BRDF through a few
fixed views; each is one function here, computed in Rust over a grid of directions in one batch, returning
NumPy arrays in a small frozen dataclass that :mod:`brdfpy.plot` draws and that tests can check:

- :func:`polar`: ``f_r(θ_o)`` in the plane of incidence (optionally × ``cos θ_o``) → :class:`Polar`;
- :func:`lobe`: the 3D lobe for one incidence, as a :class:`~brdfpy.Mesh` → :class:`Lobe`;
- :func:`half_diff_slice`: the image over Rusinkiewicz's ``(θ_h, θ_d)`` at a ``φ_d`` → :class:`HalfDiffSlice`;
- :func:`albedo`: the directional albedo ``E(θ_i)`` → :class:`Albedo`;
- :func:`albedo_table`: ``E(θ_i)`` over a range of one parameter (e.g. roughness) → :class:`AlbedoTable`;
- :func:`lit_sphere`: the lit sphere (a light and a uniform sky) → :class:`~brdfpy.Image`.

Every function takes one model or several (a list): a :class:`~brdfpy.Model`, a registry name (its defaults),
or a measured :class:`~brdfpy.measured.Tabulated`; for a list it returns a list, ready to overlay.

Frame and angles (all in **degrees** in this module): the local frame has the normal ``+z`` and, for
anisotropic models, the tangent ``+x``. The incidence is the light direction at polar angle ``θ_i`` in
``[0°, 90°]`` from the normal and azimuth ``φ`` from the tangent:
``l = (sin θ_i cos φ, sin θ_i sin φ, cos θ_i)`` (:func:`brdfpy.vectors.from_spherical`). Outgoing angles
``θ_o`` in the plane of incidence are signed, positive on the mirror side: ``θ_o = θ_i`` is the mirror
direction, ``θ_o = −θ_i`` the retro-reflection direction. Values are ``f_r`` in 1/sr per RGB channel, as
:meth:`Model.eval` returns them (a classic course model's ``f_r`` is its formula divided by ``n·l``).

>>> import brdfpy
>>> p = brdfpy.views.polar("cook_torrance", theta_i=30)
>>> float(p.theta_o[p.luminance.argmax()])  # the peak, near the mirror direction  # doctest: +SKIP
30.0
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal, Union, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import _as_numeric, as_f64, as_float, as_int, as_str
from brdfpy.image import Image
from brdfpy.measured import Tabulated
from brdfpy.mesh import Mesh
from brdfpy.models import Model, model_info
from brdfpy.vectors import from_spherical

__all__ = [
    "LUMINANCE",
    "Albedo",
    "AlbedoTable",
    "HalfDiffSlice",
    "Lobe",
    "ModelLike",
    "Polar",
    "albedo",
    "albedo_table",
    "as_model",
    "half_diff_slice",
    "lit_sphere",
    "lobe",
    "polar",
]

#: Rec. 709 luminance weights of linear RGB (ITU-R BT.709): ``Y = 0.2126 R + 0.7152 G + 0.0722 B``.
LUMINANCE = (0.2126, 0.7152, 0.0722)

#: What the view functions accept as a model: a :class:`~brdfpy.Model`, a registry name (its defaults), or a
#: measured :class:`brdfpy.measured.Tabulated`.
ModelLike = Union[Model, str, Tabulated]
#: One model, or several (a list: the view function then returns a list).
Models = Union[ModelLike, Sequence[ModelLike]]

F32 = NDArray[np.float32]
F64 = NDArray[np.float64]


def as_model(m: object) -> Model:
    """``m`` as a :class:`~brdfpy.Model`: a model as it is, a registry name with its defaults, a measured
    table through its ``as_model()``.

    Raises
    ------
    ValueError
        An unknown model name (the message lists the known ones).
    TypeError
        Anything else.
    """
    if isinstance(m, _brdfpy.Model):
        return m  # type: ignore[return-value]
    if isinstance(m, str):
        return Model(m)
    as_m = getattr(m, "as_model", None)
    if callable(as_m):
        out = as_m()
        if isinstance(out, _brdfpy.Model):
            return out  # type: ignore[return-value]
    raise TypeError(
        f"model: expected a brdfpy.Model, a model name or a measured table, got {type(m).__name__}"
    )


def _models(models: object) -> tuple[list[Model], bool]:
    """The models of a view call and whether a single one was given (then the call returns one result)."""
    if isinstance(models, (str, _brdfpy.Model)) or callable(getattr(models, "as_model", None)):
        return [as_model(models)], True
    if isinstance(models, Sequence):
        if len(models) == 0:
            raise ValueError("models: is empty; give a model, a model name or a list of them")
        return [as_model(m) for m in models], False
    raise TypeError(
        f"models: expected a brdfpy.Model, a model name, a measured table or a list of them, "
        f"got {type(models).__name__}"
    )


def _number(name: str, x: object) -> float:
    v = as_float(name, x)
    if not math.isfinite(v):
        raise ValueError(f"{name}: must be finite, got {v}")
    return v


def _int(name: str, x: object) -> int:
    # Any 64-bit integer: the compiled module checks the range of each count and names it (beyond 64 bits
    # its conversion would raise OverflowError, naming nothing).
    return as_int(name, x, -(2**63), 2**63 - 1)


def _theta_i(x: object) -> float:
    t = _number("theta_i", x)
    if not 0.0 <= t <= 90.0:
        raise ValueError(f"theta_i: must be in [0°, 90°] (the light above the surface), got {t}°")
    return t


def _luminance(values: NDArray[Any]) -> F32:
    return np.asarray(values @ np.asarray(LUMINANCE, dtype=np.float32), dtype=np.float32)


@dataclass(frozen=True)
class Polar:
    """The in-plane slice of one model for one incidence (see :func:`polar`)."""

    #: The model (``model.name`` is ``"measured"`` for a table).
    model: Model
    #: Incidence polar angle [deg].
    theta_i: float
    #: Azimuth of the plane of incidence from the tangent [deg].
    phi: float
    #: Whether :attr:`values` are multiplied by ``cos θ_o``.
    cosine: bool
    #: Signed outgoing angles [deg], ``−90 … 90``, positive on the mirror side.
    theta_o: F64
    #: ``f_r`` [1/sr] (× ``cos θ_o`` if :attr:`cosine`) per RGB channel, ``(n, 3)``.
    values: F32

    @property
    def luminance(self) -> F32:
        """Rec. 709 luminance of :attr:`values`, ``(n,)``."""
        return _luminance(self.values)


@overload
def polar(  # type: ignore[overload-overlap]  # a str is one model, though a Sequence too
    models: ModelLike, theta_i: float = ..., *, phi: float = ..., n: int = ..., cosine: bool = ...
) -> Polar: ...
@overload
def polar(
    models: Sequence[ModelLike], theta_i: float = ..., *, phi: float = ..., n: int = ..., cosine: bool = ...
) -> list[Polar]: ...
def polar(
    models: Models,
    theta_i: float = 45.0,
    *,
    phi: float = 0.0,
    n: int = 360,
    cosine: bool = False,
) -> Polar | list[Polar]:
    """``f_r`` in the plane of incidence, as the viewer sweeps from one horizon to the other.

    Parameters
    ----------
    models : model, name, measured table, or a list of them
    theta_i : float
        Incidence polar angle [deg], in ``[0, 90]``.
    phi : float
        Azimuth of the plane of incidence from the tangent [deg] (matters for anisotropic models).
    n : int
        Number of outgoing angles, equally spaced over ``[−90°, 90°]`` inclusive (at least 2).
    cosine : bool
        Multiply by ``cos θ_o``: the reflected intensity per unit incident flux, whose integral over the
        hemisphere is the directional albedo (:func:`albedo`).
    """
    ms, single = _models(models)
    t, p = _theta_i(theta_i), _number("phi", phi)
    out = []
    for m in ms:
        theta_o, values = _brdfpy.view_polar(m, math.radians(t), math.radians(p), _int("n", n), bool(cosine))
        out.append(Polar(m, t, p, bool(cosine), np.degrees(theta_o), values))
    return out[0] if single else out


@dataclass(frozen=True)
class Lobe:
    """The 3D lobe of one model for one incidence (see :func:`lobe`)."""

    #: The model.
    model: Model
    #: Incidence polar angle [deg].
    theta_i: float
    #: Incidence azimuth [deg].
    phi: float
    #: ``"f"`` or ``"f_cos"``: what the radius is.
    radius: str
    #: ``"luminance"``, ``"r"``, ``"g"`` or ``"b"``: of which number of the RGB value.
    channel: str
    #: The lobe as a triangle mesh (vertex ``k`` at ``radii[k] · directions[k]``), for
    #: :meth:`brdfpy.Scene.add` or export.
    mesh: Mesh
    #: Unit outgoing direction of each vertex ``(V, 3)``: the pole ``+z`` first, then ``n_theta`` rings
    #: from the normal to the horizon of ``n_phi`` azimuths each.
    directions: F32
    #: ``f_r`` (× ``cos θ_o`` for ``"f_cos"``) per RGB channel at each vertex ``(V, 3)``.
    values: F32
    #: Radius of each vertex ``(V,)``.
    radii: F32
    #: The light direction ``l`` (unit).
    light: F32


@overload
def lobe(  # type: ignore[overload-overlap]
    models: ModelLike,
    theta_i: float = ...,
    *,
    phi: float = ...,
    n_theta: int = ...,
    n_phi: int = ...,
    radius: Literal["f", "f_cos"] = ...,
    channel: Literal["luminance", "r", "g", "b"] = ...,
) -> Lobe: ...
@overload
def lobe(
    models: Sequence[ModelLike],
    theta_i: float = ...,
    *,
    phi: float = ...,
    n_theta: int = ...,
    n_phi: int = ...,
    radius: Literal["f", "f_cos"] = ...,
    channel: Literal["luminance", "r", "g", "b"] = ...,
) -> list[Lobe]: ...
def lobe(
    models: Models,
    theta_i: float = 45.0,
    *,
    phi: float = 0.0,
    n_theta: int = 64,
    n_phi: int = 128,
    radius: Literal["f", "f_cos"] = "f_cos",
    channel: Literal["luminance", "r", "g", "b"] = "luminance",
) -> Lobe | list[Lobe]:
    """The 3D lobe for one incidence: every outgoing direction ``v`` pushed out to a radius ``f_r(l, v)``
    (``radius="f"``) or ``f_r(l, v) cos θ_o`` (``"f_cos"``, the default: the shape of the reflected light)
    of one channel or the luminance, as a :class:`~brdfpy.Mesh` (``1 + n_theta·n_phi`` vertices) that the
    rasterizer renders (:meth:`brdfpy.Scene.add`) or that can be exported.

    Returns a :class:`Lobe` (a list of them for a list of models).
    """
    ms, single = _models(models)
    t, p = _theta_i(theta_i), _number("phi", phi)
    out = []
    for m in ms:
        verts, faces, dirs, values, radii = _brdfpy.view_lobe(
            m,
            math.radians(t),
            math.radians(p),
            _int("n_theta", n_theta),
            _int("n_phi", n_phi),
            as_str("radius", radius, '"f" or "f_cos"'),
            as_str("channel", channel, '"luminance", "r", "g" or "b"'),
        )
        mesh = Mesh(verts, faces)
        out.append(
            Lobe(m, t, p, radius, channel, mesh, dirs, values, radii, from_spherical(t, p, degrees=True))
        )
    return out[0] if single else out


@dataclass(frozen=True)
class HalfDiffSlice:
    """``f_r`` over Rusinkiewicz's half/difference angles at one ``φ_d`` (see :func:`half_diff_slice`)."""

    #: The model.
    model: Model
    #: The difference azimuth [deg].
    phi_d: float
    #: Column angles ``θ_h`` [deg], cell centres over ``[0, 90]``, ``(n_h,)``.
    theta_h: F64
    #: Row angles ``θ_d`` [deg], cell centres over ``[0, 90]``, ``(n_d,)`` (row 0 at ``θ_d ≈ 0``).
    theta_d: F64
    #: ``f_r`` [1/sr] per RGB channel, ``(n_d, n_h, 3)``.
    values: F32
    #: Where both ``l`` and ``v`` are above the surface, ``(n_d, n_h)``; elsewhere physical models are 0 by
    #: convention, not because the material is dark.
    valid: NDArray[np.bool_]

    @property
    def luminance(self) -> F32:
        """Rec. 709 luminance of :attr:`values`, ``(n_d, n_h)``."""
        return _luminance(self.values)

    def log_range(self, z: ArrayLike | None = None, *, decades: float = 4.0) -> tuple[float, float]:
        """The ``(low, high)`` [1/sr] a logarithmic colour scale of this slice should span, from the data:
        ``high`` is the 99.5th percentile of ``z`` (default: :attr:`luminance`) over the valid cells (a
        grazing Fresnel or ``1/cos`` peak in the last cells would otherwise push the body of the slice into
        the lowest colours), ``low`` its 0.5th percentile but at most ``decades`` decades below ``high``. A
        fixed floor (``high · 10⁻⁴``) would spend most colours on values the slice does not hold: a diffuse
        term plus a highlight spans about one decade and showed as one flat colour. A constant slice gets
        ``(high / 10, high)``; an all-zero one ``(0, 0)``. ``z``, when given, has the slice's shape
        ``(n_d, n_h)`` (e.g. one channel of :attr:`values`); ``decades`` is a positive number."""
        if z is None:
            z = self.luminance
        else:
            z = _as_numeric("z", z)
            if z.shape != self.valid.shape:
                raise ValueError(f"z: expected the slice's shape {self.valid.shape}, got {z.shape}")
        decades = as_float("decades", decades)
        if not (math.isfinite(decades) and decades > 0):
            raise ValueError(f"decades: must be a positive finite number, got {decades}")
        vals = z[self.valid]
        vals = vals[np.isfinite(vals) & (vals > 0)]
        if vals.size == 0:
            return 0.0, 0.0
        high = float(np.percentile(vals, 99.5))
        low = max(float(np.percentile(vals, 0.5)), high * 10.0**-decades)
        if not low < high * (1 - 1e-6):
            low = high / 10
        return low, high


@overload
def half_diff_slice(  # type: ignore[overload-overlap]
    models: ModelLike, *, phi_d: float = ..., size: int | tuple[int, int] = ...
) -> HalfDiffSlice: ...
@overload
def half_diff_slice(
    models: Sequence[ModelLike], *, phi_d: float = ..., size: int | tuple[int, int] = ...
) -> list[HalfDiffSlice]: ...
def half_diff_slice(
    models: Models,
    *,
    phi_d: float = 90.0,
    size: int | tuple[int, int] = 512,
) -> HalfDiffSlice | list[HalfDiffSlice]:
    """The image slice of BRDF Explorer (Burley 2012 §3): ``f_r`` over ``θ_h`` (columns) and ``θ_d`` (rows),
    at the difference azimuth ``φ_d`` [deg, in ``[0, 180]``; 90 is Burley's slice].

    The specular peak runs along ``θ_h = 0``, Fresnel shows along ``θ_d`` (grazing at ``θ_d → 90°``),
    retro-reflection at ``θ_d = 0``. The angles are Rusinkiewicz's (1998), computed by the same code as the
    measured-table look-up (:mod:`brdfpy.measured`). ``size`` is ``n`` (square) or ``(n_h, n_d)``, each in
    ``[1, 4096]``.

    Returns a :class:`HalfDiffSlice` (a list of them for a list of models).
    """
    ms, single = _models(models)
    pd = _number("phi_d", phi_d)
    if isinstance(size, tuple):
        if len(size) != 2:
            raise ValueError(f"size: expected n or (n_theta_h, n_theta_d), got {size!r}")
        n_h, n_d = _int("size", size[0]), _int("size", size[1])
    else:
        n_h = n_d = _int("size", size)
    out = []
    for m in ms:
        values, valid = _brdfpy.view_half_diff_slice(m, math.radians(pd), n_h, n_d)
        th = np.degrees(_brdfpy.view_cell_angles(n_h))
        td = np.degrees(_brdfpy.view_cell_angles(n_d))
        out.append(HalfDiffSlice(m, pd, th, td, values, valid))
    return out[0] if single else out


#: Default incidence angles of :func:`albedo` [deg]: 0° to 87° every 3°, and 89°. Not 90°: light at grazing
#: brings no energy, and models with a ``1/cos θ_i`` factor (Ward) are unbounded there.
ALBEDO_THETA_I = (*(3.0 * k for k in range(30)), 89.0)


@dataclass(frozen=True)
class Albedo:
    """The directional albedo curve of one model (see :func:`albedo`)."""

    #: The model.
    model: Model
    #: Incidence angles [deg], ``(K,)``.
    theta_i: F64
    #: ``E(θ_i)`` per RGB channel, ``(K, 3)``.
    values: F32

    @property
    def luminance(self) -> F32:
        """Rec. 709 luminance of :attr:`values`, ``(K,)``."""
        return _luminance(self.values)


def _theta_grid(theta_i: ArrayLike | None) -> F64:
    raw = np.asarray(ALBEDO_THETA_I) if theta_i is None else _as_numeric("theta_i", theta_i)
    t = raw.astype(np.float64).reshape(-1)
    if t.size == 0:
        raise ValueError("theta_i: is empty")
    bad = ~np.isfinite(t) | (t < 0.0) | (t > 90.0)
    if bad.any():
        raise ValueError(f"theta_i: every angle must be in [0°, 90°], got {t[bad][0]}°")
    return t


@overload
def albedo(  # type: ignore[overload-overlap]
    models: ModelLike, theta_i: ArrayLike | None = ..., *, quadrature: tuple[int, int, float] | None = ...
) -> Albedo: ...
@overload
def albedo(
    models: Sequence[ModelLike],
    theta_i: ArrayLike | None = ...,
    *,
    quadrature: tuple[int, int, float] | None = ...,
) -> list[Albedo]: ...
def albedo(
    models: Models,
    theta_i: ArrayLike | None = None,
    *,
    quadrature: tuple[int, int, float] | None = None,
) -> Albedo | list[Albedo]:
    """The directional albedo ``E(θ_i) = ∫ f_r(l, v) cos θ_o dω_v``: the fraction of the light arriving from
    ``θ_i`` that is reflected (energy conservation: ``E ≤ 1``; white Lambert gives 1).

    Parameters
    ----------
    theta_i : array_like, optional
        Incidence angles [deg] in ``[0, 90]``; default :data:`ALBEDO_THETA_I` (every 3°).
    quadrature : (theta_order, phi_order, min_panel), optional
        Settings of the graded Gauss-Legendre rule (:func:`brdfpy.checks.directional_albedo`); default
        ``(4, 4, 1e-3)``, which integrates white Lambert to 1e-6 and agrees with the checks' finer default to
        1e-3 on every registry model (sharper lobes than ~2e-3 rad need a finer rule).

    Returns an :class:`Albedo` (a list of them for a list of models).
    """
    ms, single = _models(models)
    t = _theta_grid(theta_i)
    q = _brdfpy.view_quadrature() if quadrature is None else quadrature
    if not isinstance(q, (tuple, list)) or len(q) != 3:
        raise ValueError(f"quadrature: expected (theta_order, phi_order, min_panel), got {quadrature!r}")
    orders = [as_int(f"quadrature[{i}]", q[i], 1, 64) for i in (0, 1)]
    min_panel = as_float("quadrature[2]", q[2])
    rad = np.ascontiguousarray(np.radians(t))
    out = []
    for m in ms:
        values = _brdfpy.view_albedo(m, rad, orders[0], orders[1], min_panel)
        out.append(Albedo(m, t, values))
    return out[0] if single else out


@dataclass(frozen=True)
class AlbedoTable:
    """``E(θ_i)`` for a range of values of one parameter (see :func:`albedo_table`)."""

    #: Registry name of the model.
    model: str
    #: The parameter that varies.
    param: str
    #: Its values, ``(P,)``.
    param_values: F64
    #: Incidence angles [deg], ``(K,)``.
    theta_i: F64
    #: ``E`` per RGB channel, ``(P, K, 3)``: row ``p`` is the curve at ``param_values[p]``.
    values: F32

    @property
    def luminance(self) -> F32:
        """Rec. 709 luminance of :attr:`values`, ``(P, K)``."""
        return _luminance(self.values)


def albedo_table(
    model: Model | str,
    param: str = "roughness",
    values: ArrayLike | None = None,
    theta_i: ArrayLike | None = None,
    *,
    quadrature: tuple[int, int, float] | None = None,
) -> AlbedoTable:
    """``E(θ_i, p)`` for a scalar parameter ``p`` of ``model`` (e.g. the energy a microfacet model loses as it
    gets rougher), the other parameters as in ``model`` (a name means its defaults).

    ``values`` default to 8 values evenly spaced over the parameter's documented range ``(min, max]``
    (:func:`brdfpy.model_info`; the minimum is left out, as it is often a degenerate limit such as a mirror).
    """
    base = Model(model) if isinstance(model, str) else as_model(model)
    if base.name == "measured":
        raise ValueError("model: a measured table has no parameters to vary")
    info = {p["name"]: p for p in model_info(base.name)["params"]}
    if not isinstance(param, str):
        raise TypeError(f"param: expected a parameter name (str), got {type(param).__name__}")
    if param not in info:
        raise ValueError(f"param: {base.name} has no parameter {param!r}; its parameters: {', '.join(info)}")
    spec = info[param]
    if spec["kind"] != "scalar":
        raise ValueError(f"param: {param!r} of {base.name} is a {spec['kind']}, not a scalar")
    if values is None:
        lo, hi = spec["min"], spec["max"]
        assert lo is not None and hi is not None
        # (lo, hi]: the lower bound is often a degenerate limit (roughness 0: a mirror, no lobe to integrate).
        pv = np.linspace(lo, hi, 9)[1:]
    else:
        pv = as_f64("values", values).reshape(-1)
        if pv.size == 0:
            raise ValueError("values: is empty")
    t = _theta_grid(theta_i)
    params = dict(base.params)
    curves = []
    for x in pv:
        params[param] = float(x)
        curves.append(albedo(Model(base.name, **params), t, quadrature=quadrature).values)
    return AlbedoTable(base.name, param, pv, t, np.stack(curves).astype(np.float32))


#: Tone maps :func:`lit_sphere` accepts: ``"auto"`` and the operators of :mod:`brdfpy.tonemap`.
SPHERE_TONEMAPS = ("auto", "clamp", "reinhard", "reinhard_extended", "aces")


@overload
def lit_sphere(  # type: ignore[overload-overlap]
    models: ModelLike,
    *,
    theta_i: float | None = ...,
    phi: float = ...,
    light: ArrayLike | None = ...,
    size: int = ...,
    ambient: float = ...,
    samples: int = ...,
    tangent_axis: ArrayLike = ...,
    background: float | Sequence[float] = ...,
    tonemap: str = ...,
    exposure: float = ...,
    white: float | None = ...,
) -> Image: ...
@overload
def lit_sphere(
    models: Sequence[ModelLike],
    *,
    theta_i: float | None = ...,
    phi: float = ...,
    light: ArrayLike | None = ...,
    size: int = ...,
    ambient: float = ...,
    samples: int = ...,
    tangent_axis: ArrayLike = ...,
    background: float | Sequence[float] = ...,
    tonemap: str = ...,
    exposure: float = ...,
    white: float | None = ...,
) -> list[Image]: ...
def lit_sphere(
    models: Models,
    *,
    theta_i: float | None = None,
    phi: float = 45.0,
    light: ArrayLike | None = None,
    size: int = 512,
    ambient: float = 0.05,
    samples: int = 1,
    tangent_axis: ArrayLike = (0.0, 1.0, 0.0),
    background: float | Sequence[float] = 0.0,
    tonemap: str = "auto",
    exposure: float = 0.0,
    white: float | None = None,
) -> Image | list[Image]:
    """The lit sphere of BRDF Explorer (and of ``brdfpy gallery``) as an :class:`~brdfpy.Image`.

    A unit sphere seen orthographically along ``−z`` (viewer ``v = +z``), shaded per sample from its analytic
    normal by a directional light (irradiance π at normal incidence for physical models, so a white Lambert
    sphere facing the light shows its albedo; the course formula with light colour 1 for classic models) and
    a uniform sky of radiance ``ambient`` (through the model's directional albedo).

    Parameters
    ----------
    theta_i, phi : float
        The light as an incidence in view space [deg]: ``θ_i`` from the view axis, ``φ`` from image-right
        toward image-up; the pixel whose normal is the half vector shows the specular peak. Default
        ``light=(1, 1, 1)`` (upper right, in front).
    light : 3 floats, optional
        The light direction instead (``+x`` right, ``+y`` up, ``+z`` toward the viewer).
    size : int
        Width = height in pixels, 8 to 4096.
    samples : int
        Samples per pixel along each axis (1 to 4; box-filtered).
    tangent_axis : 3 floats
        Anisotropic models' tangent field is ``t = a × n``: circles around the axis ``a`` (default image-up,
        as on a part turned on a lathe), vanishing only at ``n = ±a``, on the silhouette.
    background : float or 3 floats
        Linear RGB radiance outside the sphere.
    tonemap : str
        ``"auto"`` (default): the extended Reinhard operator with its white point at the sphere's brightest
        value (at least 1), so a sphere within [0, 1] shows unchanged and a normalised highlight keeps its
        gradient up to a white peak instead of clipping to a disc; or any :data:`brdfpy.tonemap.OPERATORS`
        name (``white`` for ``"reinhard_extended"``).
    exposure : float
        Stops applied before the operator.

    Returns an :class:`~brdfpy.Image` (a list of them for a list of models); ``image.hdr`` holds the linear
    radiance, ``image.mask`` the disc.
    """
    ms, single = _models(models)
    if light is not None and theta_i is not None:
        raise ValueError("light, theta_i: give the light as a direction or as an incidence, not both")
    if theta_i is not None:
        lv = from_spherical(_theta_i(theta_i), _number("phi", phi), degrees=True).astype(np.float64)
    else:
        lv = _as_numeric("light", (1.0, 1.0, 1.0) if light is None else light).astype(np.float64)
    if lv.shape != (3,) or not np.all(np.isfinite(lv)) or not np.any(lv != 0):
        raise ValueError(f"light: expected 3 finite numbers, not all zero, got {light!r}")
    axis = _as_numeric("tangent_axis", tangent_axis).astype(np.float64)
    if axis.shape != (3,) or not np.all(np.isfinite(axis)) or not np.any(axis != 0):
        raise ValueError(f"tangent_axis: expected 3 finite numbers, not all zero, got {tangent_axis!r}")
    bg = _as_numeric("background", background).astype(np.float64)
    if bg.shape not in ((), (1,), (3,)):
        raise ValueError(f"background: expected a number or 3 numbers (linear RGB), got shape {bg.shape}")
    bg = np.broadcast_to(bg, (3,))
    if not isinstance(tonemap, str) or tonemap.lower() not in SPHERE_TONEMAPS:
        raise ValueError(f"tonemap: expected one of {', '.join(SPHERE_TONEMAPS)}, got {tonemap!r}")
    op = tonemap.lower()
    if op == "auto":
        op, wp = "reinhard_extended", None if white is None else _number("white", white)
    else:
        wp = None if white is None else _number("white", white)
        if op == "reinhard_extended" and wp is None:
            wp = 4.0
    images = []
    for m in ms:
        frame = _brdfpy.view_lit_sphere(
            m,
            _int("size", size),
            [float(x) for x in lv / np.linalg.norm(lv)],
            _number("ambient", ambient),
            _int("samples", samples),
            [float(x) for x in axis],
            [float(x) for x in bg],
            op,
            _number("exposure", exposure),
            wp,
        )
        images.append(Image(frame))
    return images[0] if single else images
