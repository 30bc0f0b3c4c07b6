"""The lit-sphere contact sheet: one sphere per model, shaded per pixel from its analytic normal.

Each sphere is the unit sphere seen orthographically along −z (the viewer direction is ``v = +z`` at every
pixel), lit by one directional light (a :class:`brdfpy.DirectionalLight`: its direction is the direction in
which the light travels, as everywhere in brdfpy) and a uniform sky:

* the light: ``π · shade(l, v, n)`` for physical models, i.e. irradiance ``E = π`` at normal incidence, so
  that a white Lambert surface facing the light shows its albedo; ``shade(l, v, n)`` (the course formula
  exactly as written, light color 1) for classic models, which puts both kinds on the same scale;
* the sky (a small ambient term): a uniform sky of radiance ``ambient`` reflects ``ambient · ρ(θ_v)``, where
  ``ρ`` is the model's directional albedo (brdf-core `views::albedo`, tabulated over
  ``cos θ_v`` and interpolated per pixel); for classic models ``ρ/π``, with the same scale as above.

Anisotropic models get the tangent field ``t = a × n`` around the vertical axis ``a = +y`` (circles of
latitude, as on a part turned on a lathe): every tangent field on a sphere vanishes somewhere, and this one
only at ``n = ±a``, the top and bottom of the silhouette, where the sphere is seen edge-on, so the highlight
of Ward or Ashikhmin-Shirley stretches smoothly across the disc. The HDR result goes through
``exposure → tone map → sRGB → 8 bits``. The default tone map, ``"auto"``, is Reinhard's extended operator
(Reinhard et al. 2002, eq. 4) with its white point at each sphere's brightest value (at least 1): a sphere
within [0, 1] shows unchanged, and the highlight of a normalised Phong or Blinn-Phong lobe (many times
brighter than its diffuse part) keeps its fall-off up to a white peak instead of clipping to a white disc;
each sphere is then scaled to its own peak, so compare highlight shapes, not brightness, across spheres.
Every sphere is :func:`brdfpy.views.lit_sphere` (2×2 samples per pixel).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from brdfpy import tonemap, views
from brdfpy.lights import DirectionalLight
from brdfpy.models import model, models

__all__ = ["DEFAULT_LIGHT", "render_gallery", "save_gallery", "sphere_geometry"]

#: The gallery's light: travelling along (−1, −1, −1), i.e. coming from the upper right, in front.
DEFAULT_LIGHT = DirectionalLight((-1.0, -1.0, -1.0))

_BACKGROUND = (24, 24, 28)
_LABEL = (230, 230, 230)
_SUBLABEL = (150, 150, 160)


def sphere_geometry(size: int) -> tuple[NDArray[np.bool_], NDArray[np.float32], NDArray[np.float32]]:
    """Pixels of a unit sphere filling a ``size × size`` square, seen orthographically along −z.

    Returns the ``(size, size)`` coverage mask (pixel centres inside the disc), and for the covered pixels in
    row-major order (row 0 at the top) the unit normals ``(K, 3)`` and the gallery's tangents ``(K, 3)``,
    ``+y × n`` (circles around the vertical axis; zero only at the top and bottom of the silhouette).
    """
    c = (np.arange(size, dtype=np.float64) + 0.5) / size * 2.0 - 1.0
    x, y = np.meshgrid(c, -c)  # image rows go down, y goes up
    r2 = x * x + y * y
    mask = r2 < 1.0
    xs, ys = x[mask], y[mask]
    zs = np.sqrt(np.maximum(1.0 - r2[mask], 0.0))
    n = np.stack([xs, ys, zs], axis=-1).astype(np.float32)
    t = np.stack([zs, np.zeros_like(xs), -xs], axis=-1).astype(np.float32)
    return mask, n, t


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
    light: DirectionalLight = DEFAULT_LIGHT,
    size: int = 160,
    columns: int | None = None,
    tonemap_operator: str = "auto",
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
    light : DirectionalLight
        The light; its direction is the direction of **travel** (``DirectionalLight((-1, 0, 0))`` comes
        from the right). Each sphere is lit with the gallery's own scale (see the module documentation),
        so the light must have color and intensity 1; brighten with ``exposure``.
    size : int
        Sphere diameter in pixels (16 to 2048).
    columns : int, optional
        Spheres per row (default: about the square root of the count, plus one).
    tonemap_operator : str
        ``"auto"`` (see the module docs) or one of :data:`brdfpy.tonemap.OPERATORS` (``"clamp"``: values
        above 1 saturate).
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
    if not isinstance(light, DirectionalLight):
        hint = ""
        if isinstance(light, (Sequence, np.ndarray)) and np.shape(light) == (3,):
            toward = tuple(float(x) for x in np.asarray(light, dtype=np.float64))
            away = tuple(-x if x else 0.0 for x in toward)
            hint = (
                f"; three numbers are ambiguous: a light coming from {toward} (the direction toward it) is "
                f"DirectionalLight({away}), which travels along {away}"
            )
        raise TypeError(f"light: expected a brdfpy.DirectionalLight, got {type(light).__name__}{hint}")
    if light.emitted != (1.0, 1.0, 1.0):
        raise ValueError(
            f"light: the gallery lights every sphere on its own scale and needs color and intensity 1 "
            f"(got color {light.color}, intensity {light.intensity}); use exposure= to brighten"
        )
    # views.lit_sphere takes the direction toward the light (the l of the reflectance models).
    lv = -np.asarray(light.direction, dtype=np.float64)
    if not (math.isfinite(ambient) and ambient >= 0):
        raise ValueError(f"ambient: expected a finite number >= 0, got {ambient}")
    if tonemap_operator not in views.SPHERE_TONEMAPS:
        raise ValueError(
            f"tonemap: expected one of {', '.join(views.SPHERE_TONEMAPS)}, got {tonemap_operator!r}"
        )
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

    bg = tonemap.srgb_decode(np.array(_BACKGROUND, dtype=np.float32) / 255.0)
    for i, m in enumerate(built):
        img = views.lit_sphere(
            m,
            light=lv,
            size=size,
            samples=2,
            ambient=ambient,
            background=[float(x) for x in bg],
            tonemap=tonemap_operator,
            exposure=exposure,
        )
        pixels = img.rgb.copy()
        # Pixels wholly off the sphere get the sheet's exact background (the tone map moves it by a level).
        pixels[~img.mask & np.all(img.hdr == bg, axis=-1)] = _BACKGROUND
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
