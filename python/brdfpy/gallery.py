"""The lit-sphere contact sheet: one sphere per model, shaded per pixel from its analytic normal.

Each sphere is the unit sphere seen orthographically along −z (the viewer direction is ``v = +z`` at every
pixel), lit by one directional light and a uniform sky:

* the light: ``π · shade(l, v, n)`` for physical models, i.e. irradiance ``E = π`` at normal incidence, so
  that a white Lambert surface facing the light shows its albedo; ``shade(l, v, n)`` (the course formula
  exactly as written, light color 1) for classic models, which puts both kinds on the same scale;
* the sky (a small ambient term): a uniform sky of radiance ``ambient`` reflects ``ambient · ρ(θ_v)``, where
  ``ρ`` is the model's directional albedo (:func:`brdfpy.checks.directional_albedo`, tabulated over
  ``cos θ_v`` and interpolated per pixel); for classic models ``ρ/π``, with the same scale as above.

Anisotropic models get the tangent field ``t = (−y, x, 0)`` (circles around the view axis), so their
highlights stretch along concentric rings. The HDR result goes through ``exposure → tone map or clamp →
sRGB → 8 bits`` (:mod:`brdfpy.tonemap`). Every model's sphere is one batched :meth:`Model.shade` call over
all its pixels (2×2 samples per pixel, averaged after tone mapping, so the silhouettes are anti-aliased).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from brdfpy import checks, tonemap
from brdfpy.models import Model, model, models

__all__ = ["DEFAULT_LIGHT", "render_gallery", "save_gallery", "sphere_geometry"]

#: Direction toward the light: upper right, in front (the anchor scene's directional light, SCENE.md).
DEFAULT_LIGHT = (1.0, 1.0, 1.0)

_BACKGROUND = (24, 24, 28)
_LABEL = (230, 230, 230)
_SUBLABEL = (150, 150, 160)
# View cosines at which the sky term's directional albedo is tabulated (interpolated in between).
_SKY_COS = np.linspace(0.02, 1.0, 12, dtype=np.float32)


def sphere_geometry(size: int) -> tuple[NDArray[np.bool_], NDArray[np.float32], NDArray[np.float32]]:
    """Pixels of a unit sphere filling a ``size × size`` square, seen orthographically along −z.

    Returns the ``(size, size)`` coverage mask (pixel centres inside the disc), and for the covered pixels in
    row-major order (row 0 at the top) the unit normals ``(K, 3)`` and tangents ``(K, 3)`` ``(−y, x, 0)``
    (zero at the centre, where the core then picks an arbitrary frame).
    """
    c = (np.arange(size, dtype=np.float64) + 0.5) / size * 2.0 - 1.0
    x, y = np.meshgrid(c, -c)  # image rows go down, y goes up
    r2 = x * x + y * y
    mask = r2 < 1.0
    xs, ys = x[mask], y[mask]
    n = np.stack([xs, ys, np.sqrt(np.maximum(1.0 - r2[mask], 0.0))], axis=-1).astype(np.float32)
    t = np.stack([-ys, xs, np.zeros_like(xs)], axis=-1).astype(np.float32)
    return mask, n, t


def _shade_sphere(
    m: Model, light: NDArray[np.float32], ambient: float, n: NDArray[np.float32], t: NDArray[np.float32]
) -> NDArray[np.float32]:
    v = np.array([0.0, 0.0, 1.0], dtype=np.float32)
    scale = math.pi if m.physical else 1.0
    rgb = scale * m.shade(light, v, n, t if m.anisotropic else None)
    if ambient > 0.0:
        # Coarse quadrature: the sky only needs to show the unlit side, not to be a measurement.
        albedo = checks.directional_albedo(m, _SKY_COS, 4, 4, min_panel=1e-3)
        if not m.physical:
            albedo = albedo / np.float32(math.pi)
        cos_v = n[:, 2]
        for ch in range(3):
            rgb[:, ch] += np.float32(ambient) * np.interp(cos_v, _SKY_COS, albedo[:, ch]).astype(np.float32)
    return rgb


def _operator(rgb: NDArray[np.float32], name: str) -> NDArray[np.float32]:
    """HDR → [0, 1] by the named tone-mapping operator (still linear)."""
    if name == "reinhard_extended":
        return tonemap.reinhard_extended(rgb)
    op = {"clamp": tonemap.clamp, "reinhard": tonemap.reinhard, "aces": tonemap.aces}[name]
    return op(rgb)


def _font(px: int) -> Any:
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=px)  # Pillow >= 10.1 with FreeType: a scalable default font
    except TypeError:
        return ImageFont.load_default()


def _centered(draw: Any, cx: int, top: int, text: str, fill: tuple[int, int, int], font: Any) -> None:
    # Measured by hand: anchors are not supported by Pillow's bitmap default font.
    width = draw.textlength(text, font=font)
    draw.text((cx - width / 2, top), text, fill=fill, font=font)


def _fit(draw: Any, text: str, font: Any, width: int) -> str:
    """``text``, shortened with an ellipsis until it is at most ``width`` pixels wide."""
    if draw.textlength(text, font=font) <= width:
        return text
    while text and draw.textlength(text + "…", font=font) > width:
        text = text[:-1]
    return text + "…"


def render_gallery(
    names: Sequence[str] | None = None,
    params: Mapping[str, Mapping[str, Any]] | None = None,
    *,
    light: Sequence[float] = DEFAULT_LIGHT,
    size: int = 160,
    columns: int | None = None,
    tonemap_operator: str = "clamp",
    exposure: float = 0.0,
    ambient: float = 0.05,
) -> NDArray[np.uint8]:
    """Render the contact sheet as an ``(H, W, 3)`` uint8 sRGB image.

    Parameters
    ----------
    names : sequence of str, optional
        Models to show, in this order (default: every registered model).
    params : mapping, optional
        ``{model name: {parameter: value}}`` overriding defaults.
    light : 3 floats
        Direction toward the light (normalised; need not be unit length).
    size : int
        Sphere diameter in pixels (16 to 2048).
    columns : int, optional
        Spheres per row (default: about the square root of the count, plus one).
    tonemap_operator : str
        One of :data:`brdfpy.tonemap.OPERATORS` (``"clamp"``: values above 1 saturate).
    exposure : float
        Exposure in stops applied before the operator.
    ambient : float
        Radiance of the uniform sky (0 turns it off).
    """
    from PIL import Image, ImageDraw

    names = list(models()) if names is None else list(names)
    params = dict(params or {})
    if not names:
        raise ValueError("models: the gallery needs at least one model")
    unknown = [k for k in params if k not in names]
    if unknown:
        raise ValueError(f"params: given for {unknown}, which are not in the gallery ({', '.join(names)})")
    if not 16 <= size <= 2048:
        raise ValueError(f"size: expected 16 to 2048 pixels, got {size}")
    lv = np.asarray(light, dtype=np.float64)
    if lv.shape != (3,) or not np.all(np.isfinite(lv)) or not np.any(lv != 0):
        raise ValueError(f"light: expected 3 finite numbers, not all zero, got {light}")
    if not (math.isfinite(ambient) and ambient >= 0):
        raise ValueError(f"ambient: expected a finite number >= 0, got {ambient}")
    if tonemap_operator not in tonemap.OPERATORS:
        raise ValueError(f"tonemap: expected one of {', '.join(tonemap.OPERATORS)}, got {tonemap_operator!r}")
    built = [model(name, **params.get(name, {})) for name in names]

    cols = columns if columns is not None else min(len(built), math.isqrt(len(built) - 1) + 2)
    if cols < 1:
        raise ValueError(f"columns: expected at least 1, got {cols}")
    rows = math.ceil(len(built) / cols)
    font_px = max(11, size // 11)
    pad, label_h = max(8, size // 12), 2 * font_px + 8
    cell_w, cell_h = size + 2 * pad, size + pad + label_h
    sheet = Image.new("RGB", (cols * cell_w, rows * cell_h + pad), _BACKGROUND)
    draw = ImageDraw.Draw(sheet)
    font, small = _font(font_px), _font(max(9, font_px * 3 // 4))

    # Shade at 2×2 samples per pixel and average the tone-mapped (display-linear) values, so that the
    # silhouettes are anti-aliased; every sample is one element of the model's single batched call.
    ss = 2
    mask, n, t = sphere_geometry(size * ss)
    light32 = (lv / np.linalg.norm(lv)).astype(np.float32)
    background = tonemap.srgb_decode(np.array(_BACKGROUND, dtype=np.float32) / 255.0)
    for i, m in enumerate(built):
        rgb = _shade_sphere(m, light32, ambient, n, t)
        if exposure != 0.0:
            rgb = tonemap.exposure(rgb, exposure)
        linear = np.empty((size * ss, size * ss, 3), dtype=np.float32)
        linear[:] = background
        linear[mask] = _operator(rgb, tonemap_operator)
        linear = linear.reshape(size, ss, size, ss, 3).mean(axis=(1, 3))
        pixels = tonemap.to_uint8(linear, "clamp")
        x0, y0 = (i % cols) * cell_w + pad, (i // cols) * cell_h + pad
        sheet.paste(Image.fromarray(pixels, "RGB"), (x0, y0))
        cx, ty = x0 + size // 2, y0 + size + 4
        _centered(draw, cx, ty, m.name, _LABEL, font)
        given = params.get(m.name, {})
        detail = (
            ", ".join(f"{k}={v}" for k, v in given.items())
            if given
            else ("physical" if m.physical else "classic")
        )
        _centered(draw, cx, ty + font_px + 3, _fit(draw, detail, small, cell_w - 6), _SUBLABEL, small)
    return np.asarray(sheet, dtype=np.uint8)


def save_gallery(path: str | Path, **kwargs: Any) -> tuple[int, int]:
    """Render with :func:`render_gallery` (same keyword arguments) and save a PNG.

    Returns ``(width, height)`` in pixels.
    """
    from PIL import Image

    img = render_gallery(**kwargs)
    Image.fromarray(img, "RGB").save(Path(path), format="PNG")
    return img.shape[1], img.shape[0]
