"""Plots of the BRDF Explorer views (:mod:`brdfpy.views`) on matplotlib, the optional extra ``brdfpy[plot]``.

Every function draws into a given matplotlib ``Axes`` (``ax=``) or a new figure, and returns the ``Axes`` (the
dashboard returns its ``Figure``) so that it can be restyled or saved. Several models overlay in distinct
colours (matplotlib's ``tab10`` cycle) with a legend; axes are labelled with their units. Angles are in
degrees, as in :mod:`brdfpy.views`.

>>> import brdfpy.plot
>>> fig = brdfpy.plot.dashboard(["cook_torrance", "blinn_phong"], theta_i=30)  # doctest: +SKIP
>>> fig.savefig("brdf.png")  # doctest: +SKIP

``import brdfpy`` does not import matplotlib; importing this module does (and raises an ``ImportError`` that
names the extra when it is missing).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import views
from brdfpy.models import Model
from brdfpy.views import ModelLike, Models

try:
    import matplotlib as mpl
    import matplotlib.colors as mcolors
    import matplotlib.pyplot as plt
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
except ImportError as e:  # pragma: no cover - exercised by the packaging, not the tests
    raise ImportError(
        "brdfpy.plot needs matplotlib: pip install 'brdfpy[plot]' (or pip install matplotlib)"
    ) from e

__all__ = [
    "VIEWS",
    "albedo",
    "albedo_table",
    "dashboard",
    "half_diff_slice",
    "lit_sphere",
    "lobe",
    "polar",
]

#: The views :func:`dashboard` and ``brdfpy plot --view`` know.
VIEWS = ("polar", "lobe", "slice", "albedo", "sphere")

Channel = Literal["luminance", "r", "g", "b"]
_CHANNELS = {"luminance": None, "r": 0, "g": 1, "b": 2}


def _colors(k: int) -> list[str]:
    cycle = [mcolors.to_hex(c) for c in mpl.colormaps["tab10"].colors]  # type: ignore[attr-defined]
    return [cycle[i % len(cycle)] for i in range(k)]


def _channel(values: NDArray[np.float32], channel: str) -> NDArray[np.float64]:
    if channel not in _CHANNELS:
        raise ValueError(f"channel: expected one of {', '.join(_CHANNELS)}, got {channel!r}")
    c = _CHANNELS[channel]
    v = values.astype(np.float64)
    return v @ np.asarray(views.LUMINANCE) if c is None else v[..., c]


def _label(m: Model) -> str:
    return m.name


def _new_axes(projection: str | None = None) -> Axes:
    fig = plt.figure(figsize=(5.0, 4.2), layout="constrained")
    return fig.add_subplot(projection=projection)


def _listify(models: Models) -> list[Model]:
    return views._models(models)[0]


def polar(
    models: Models,
    theta_i: float = 45.0,
    *,
    phi: float = 0.0,
    cosine: bool = False,
    log: bool = False,
    decades: float = 4.0,
    channel: Channel = "luminance",
    n: int = 360,
    ax: Axes | None = None,
) -> Axes:
    """Polar plot of ``f_r`` in the plane of incidence (:func:`brdfpy.views.polar`) on a polar ``Axes``.

    The normal points up, the light comes from the left at ``θ_i`` (grey arrow), the mirror direction is
    the dashed line on the right. ``log=True`` plots ``log10 f_r`` over ``decades`` decades below the
    largest value. One line per model (``ax.lines`` in model order, then the two direction lines).
    """
    ms = _listify(models)
    if ax is None:
        ax = _new_axes("polar")
    if getattr(ax, "name", "") != "polar":
        raise ValueError("ax: expected a polar Axes (projection='polar')")
    data = views.polar(ms, theta_i, phi=phi, n=n, cosine=cosine)
    ys = [_channel(p.values, channel) for p in data]
    # The scale comes from the directions at least 5° off the horizon: some models (Ward's 1/sqrt(cos θ_i
    # cos θ_o)) peak at grazing, which would flatten every other line; such a peak runs off the edge.
    inner = np.abs(data[0].theta_o) <= 85.0
    top = max(float(y[inner].max()) for y in ys)
    if log:
        floor = (top if top > 0 else 1.0) * 10.0**-decades
    for p, y, c in zip(data, ys, _colors(len(data))):
        r = np.log10(np.maximum(y, floor) / floor) if log else y
        ax.plot(np.radians(p.theta_o), r, color=c, lw=1.6, label=_label(p.model), clip_on=True)
    pax: Any = ax
    pax.set_theta_zero_location("N")
    pax.set_theta_direction(-1)
    pax.set_thetamin(-90)
    pax.set_thetamax(90)
    rmax = (decades if log else top) * 1.05 or 1.0
    ax.set_ylim(0, rmax)
    ti = math.radians(data[0].theta_i)
    ax.plot([-ti, -ti], [0, rmax], color="0.45", lw=1.2)
    ax.annotate(
        "", xy=(-ti, 0.05 * rmax), xytext=(-ti, rmax), arrowprops={"arrowstyle": "->", "color": "0.45"}
    )
    ax.plot([ti, ti], [0, rmax], color="0.45", lw=0.9, ls="--")
    what = "f_r cos θ_o" if cosine else "f_r"
    if log:
        ticks = np.arange(0, int(decades) + 1)
        ax.set_yticks(ticks)
        ax.set_yticklabels([f"{floor * 10.0**k:.1e}" for k in ticks], fontsize=7)
    ax.set_title(
        f"in-plane slice, θ_i = {data[0].theta_i:g}°, φ = {data[0].phi:g}°\n"
        f"angle θ_o [°] (mirror side right), radius {what} [1/sr]{' (log)' if log else ''}",
        fontsize=9,
    )
    ax.legend(loc="upper left", bbox_to_anchor=(-0.1, 1.0), fontsize=8, frameon=False)
    return ax


def lobe(
    models: Models,
    theta_i: float = 45.0,
    *,
    phi: float = 0.0,
    radius: Literal["f", "f_cos"] = "f_cos",
    channel: Channel = "luminance",
    n_theta: int = 32,
    n_phi: int = 64,
    ax: Axes | None = None,
) -> Axes:
    """The 3D lobe (:func:`brdfpy.views.lobe`) as translucent surfaces on a 3D ``Axes``, one per model, with
    the light direction as an arrow. Axes are equal, in the unit of the radius (1/sr)."""
    ms = _listify(models)
    # mpl_toolkits.mplot3d has no type information: the 3D methods are reached through Any.
    ax3: Any = _new_axes("3d") if ax is None else ax
    if getattr(ax3, "name", "") != "3d":
        raise ValueError("ax: expected a 3D Axes (projection='3d')")
    data = views.lobe(ms, theta_i, phi=phi, n_theta=n_theta, n_phi=n_phi, radius=radius, channel=channel)
    extent = max(float(lb.radii.max()) for lb in data) or 1.0
    for lb, c in zip(data, _colors(len(data))):
        v = lb.mesh.vertices
        grid = v[1:].reshape(n_theta, n_phi, 3)
        grid = np.concatenate([np.broadcast_to(v[0], (1, n_phi, 3)), grid], axis=0)
        grid = np.concatenate([grid, grid[:, :1]], axis=1)  # close the azimuth seam
        ax3.plot_surface(
            grid[..., 0],
            grid[..., 1],
            grid[..., 2],
            color=c,
            alpha=0.45,
            linewidth=0.2,
            edgecolor=c,
            label=_label(lb.model),
        )
    l = data[0].light * extent * 1.1
    ax3.quiver(l[0], l[1], l[2], -l[0], -l[1], -l[2], color="0.3", arrow_length_ratio=0.08, linewidth=1.2)
    ax3.set_xlim(-extent, extent)
    ax3.set_ylim(-extent, extent)
    ax3.set_zlim(0, extent)
    ax3.set_box_aspect((2, 2, 1))
    unit = "f_r cos θ_o" if radius == "f_cos" else "f_r"
    ax3.set_xlabel("x (tangent) [1/sr]", fontsize=8)
    ax3.set_ylabel("y [1/sr]", fontsize=8)
    ax3.set_zlabel("z (normal) [1/sr]", fontsize=8)
    ax3.set_title(f"lobe, radius {unit}, θ_i = {data[0].theta_i:g}°", fontsize=10)
    ax3.legend(fontsize=8, loc="upper left", frameon=False)
    ax3.view_init(elev=20, azim=-60 + data[0].phi)
    return ax3  # type: ignore[no-any-return]


def half_diff_slice(
    model: ModelLike,
    *,
    phi_d: float = 90.0,
    size: int = 256,
    log: bool = True,
    decades: float = 4.0,
    channel: Channel = "luminance",
    ax: Axes | None = None,
) -> Axes:
    """Heat map of ``f_r`` over ``(θ_h, θ_d)`` (:func:`brdfpy.views.half_diff_slice`), Burley's image slice:
    ``θ_h`` right, ``θ_d`` up, a logarithmic colour scale by default spanning the slice's own values (at most
    ``decades`` decades: :meth:`~brdfpy.views.HalfDiffSlice.log_range`), and plain grey where the light or the
    viewer is below the horizon; the colours top out at the 99.5th percentile (brighter cells saturate). The
    image is ``ax.images[0]`` (its data: the channel, masked off the valid region)."""
    s = views.half_diff_slice(model, phi_d=phi_d, size=size)
    if ax is None:
        ax = _new_axes()
    z = _channel(s.values, channel)
    low, top = s.log_range(z, decades=decades)
    data = np.ma.masked_array(z, mask=~s.valid)
    if log and top > 0:
        norm: mcolors.Normalize = mcolors.LogNorm(vmin=low, vmax=top, clip=True)
        data = np.ma.masked_array(np.maximum(z, low), mask=~s.valid)
    else:
        norm = mcolors.Normalize(vmin=0.0, vmax=top or 1.0)
    cmap = mpl.colormaps["magma"].with_extremes(bad="0.6")
    im = ax.imshow(data, origin="lower", extent=(0, 90, 0, 90), cmap=cmap, norm=norm, interpolation="nearest")
    ax.figure.colorbar(im, ax=ax, label="f_r [1/sr]" + (" (log)" if log else ""), shrink=0.85)
    ax.set_xlabel("θ_h [°]")
    ax.set_ylabel("θ_d [°]")
    ax.set_title(f"{_label(s.model)}: θ_h/θ_d slice, φ_d = {s.phi_d:g}°", fontsize=10)
    return ax


def albedo(
    models: Models,
    *,
    theta_i: ArrayLike | None = None,
    channel: Channel = "luminance",
    ax: Axes | None = None,
) -> Axes:
    """Directional albedo curves ``E(θ_i)`` (:func:`brdfpy.views.albedo`), one line per model (``ax.lines``
    in model order; then the dotted reference line at 1)."""
    ms = _listify(models)
    if ax is None:
        ax = _new_axes()
    data = views.albedo(ms, theta_i)
    top = 1.0
    for a, c in zip(data, _colors(len(data))):
        e = _channel(a.values, channel)
        ax.plot(a.theta_i, e, color=c, lw=1.6, label=_label(a.model))
        # As in polar(): a grazing blow-up (Ward) must not set the scale.
        inner = a.theta_i <= 85.0
        top = max(top, float(e[inner].max()) if inner.any() else float(e.max()))
    ax.axhline(1.0, color="0.5", lw=0.8, ls=":")
    ax.set_xlim(0, 90)
    ax.set_ylim(0, 1.1 * top)
    ax.set_xlabel("θ_i [°]")
    ax.set_ylabel("directional albedo E(θ_i) [1]")
    ax.set_title("energy reflected from light at θ_i", fontsize=10)
    ax.legend(fontsize=8, frameon=False)
    ax.grid(alpha=0.3)
    return ax


def albedo_table(
    model: Model | str,
    param: str = "roughness",
    values: ArrayLike | None = None,
    *,
    theta_i: ArrayLike | None = None,
    channel: Channel = "luminance",
    ax: Axes | None = None,
) -> Axes:
    """``E(θ_i)`` for several values of one parameter (:func:`brdfpy.views.albedo_table`), coloured by the
    parameter's value (viridis) with a colour bar."""
    t = views.albedo_table(model, param, values, theta_i)
    if ax is None:
        ax = _new_axes()
    lo, hi = float(t.param_values.min()), float(t.param_values.max())
    # Exponents spanning decades (shininess 1 to 1000) get a logarithmic colour scale.
    norm: mcolors.Normalize = (
        mcolors.LogNorm(vmin=lo, vmax=hi)
        if lo > 0 and hi / lo > 20
        else mcolors.Normalize(lo, hi if hi > lo else lo + 1)
    )
    cmap = mpl.colormaps["viridis"]
    for p, row in zip(t.param_values, _channel(t.values, channel)):
        ax.plot(t.theta_i, row, color=cmap(norm(p)), lw=1.4)
    unit = next(
        (p["unit"] for p in __import__("brdfpy").model_info(t.model)["params"] if p["name"] == param), ""
    )
    ax.figure.colorbar(
        mpl.cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax, label=f"{param} [{unit}]" if unit else param
    )
    ax.axhline(1.0, color="0.5", lw=0.8, ls=":")
    ax.set_xlim(0, 90)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("θ_i [°]")
    ax.set_ylabel("directional albedo E(θ_i) [1]")
    ax.set_title(f"{t.model}: E(θ_i) over {param}", fontsize=10)
    ax.grid(alpha=0.3)
    return ax


def lit_sphere(
    models: Models,
    *,
    theta_i: float | None = None,
    phi: float = 45.0,
    size: int = 256,
    axes: Sequence[Axes] | None = None,
    **options: Any,
) -> list[Axes]:
    """Lit spheres (:func:`brdfpy.views.lit_sphere`, same options) side by side, one ``Axes`` per model with
    its name; returns the ``Axes`` (each shows its image as ``ax.images[0]``)."""
    ms = _listify(models)
    images = views.lit_sphere(ms, theta_i=theta_i, phi=phi, size=size, samples=2, **options)
    if axes is None:
        fig = plt.figure(figsize=(2.4 * len(ms), 2.6), layout="constrained")
        axes = [fig.add_subplot(1, len(ms), k + 1) for k in range(len(ms))]
    if len(axes) != len(ms):
        raise ValueError(f"axes: {len(axes)} axes for {len(ms)} models")
    for ax, img, m in zip(axes, images, views._models(ms)[0]):
        ax.imshow(img.rgb, interpolation="antialiased")
        ax.set_title(_label(m), fontsize=9)
        ax.set_axis_off()
    return list(axes)


def dashboard(
    models: Models,
    theta_i: float = 45.0,
    *,
    phi: float = 0.0,
    views_: Sequence[str] = VIEWS,
    figsize: tuple[float, float] | None = None,
) -> Figure:
    """Every view of one or several models in one figure: the polar slice, the lobe and the albedo curves
    (overlaid), and per model its lit sphere and θ_h/θ_d slice. ``views_`` picks a subset of :data:`VIEWS`.
    Returns the ``Figure``."""
    ms = views._models(models)[0]
    unknown = [v for v in views_ if v not in VIEWS]
    if unknown or not views_:
        raise ValueError(f"views: expected some of {', '.join(VIEWS)}, got {list(views_)!r}")
    shared = [v for v in ("polar", "lobe", "albedo") if v in views_]
    per_model = [(m, v) for m in ms for v in ("sphere", "slice") if v in views_]
    cols = 3
    rows = (1 if shared else 0) + math.ceil(len(per_model) / cols)
    fig = plt.figure(figsize=figsize or (15.0, 4.6 * rows), layout="constrained")
    grid = fig.add_gridspec(rows, cols)
    for k, v in enumerate(shared):
        if v == "polar":
            polar(ms, theta_i, phi=phi, ax=fig.add_subplot(grid[0, k], projection="polar"))
        elif v == "lobe":
            lobe(ms, theta_i, phi=phi, ax=fig.add_subplot(grid[0, k], projection="3d"))
        else:
            albedo(ms, ax=fig.add_subplot(grid[0, k]))
    first = 1 if shared else 0
    for k, (m, v) in enumerate(per_model):
        ax = fig.add_subplot(grid[first + k // cols, k % cols])
        if v == "sphere":
            lit_sphere(m, theta_i=theta_i, phi=phi, axes=[ax])
            ax.set_title(f"{_label(m)}: lit sphere, light at θ_i = {theta_i:g}°", fontsize=10)
        else:
            half_diff_slice(m, ax=ax)
    return fig
