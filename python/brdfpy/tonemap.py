"""From linear HDR radiance to display values: clamp, tone-mapping operators, exposure, sRGB, 8 bits.

Every function works channel by channel on arrays of any shape (typically an ``(H, W, 3)`` image or ``(N, 3)``
colors) and returns float32 (uint8 for :func:`to_uint8`) of the same shape. They accept any float input:
NaN and negative values count as 0 and ``+inf`` as the largest float, so no operator returns NaN and an
image with one bad pixel still saves (brdf-core ``tonemap``).

The pipeline for writing an 8-bit image is ``exposure → operator → srgb_encode → 8 bits``, which is
:func:`to_uint8`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import as_float, as_scalars, as_str

__all__ = [
    "OPERATORS",
    "aces",
    "clamp",
    "exposure",
    "reinhard",
    "reinhard_extended",
    "srgb_decode",
    "srgb_encode",
    "to_uint8",
]

#: Names accepted by ``to_uint8(x, operator=...)``.
OPERATORS: tuple[str, ...] = tuple(_brdfpy.tonemap_operators())


def _finite(name: str, x: float) -> float:
    y = as_float(name, x)
    if not math.isfinite(y):
        raise ValueError(f"{name}: must be finite, got {x}")
    return y


def clamp(x: ArrayLike) -> NDArray[np.float32]:
    """Clamp to ``[0, 1]``: 0 below 0, ``x`` in ``[0, 1]``, 1 above; NaN → 0."""
    return _brdfpy.clamp(as_scalars("x", x))


def reinhard(x: ArrayLike) -> NDArray[np.float32]:
    """Simple Reinhard operator ``x / (1 + x)`` per channel (Reinhard et al. 2002, eq. 3).

    Maps ``[0, ∞)`` onto ``[0, 1)``.
    """
    return _brdfpy.reinhard(as_scalars("x", x))


def reinhard_extended(x: ArrayLike, white: float = 4.0) -> NDArray[np.float32]:
    """Extended Reinhard ``x (1 + x/w²) / (1 + x)`` per channel (Reinhard et al. 2002, eq. 4).

    1 for ``x ≥ w``; ``white`` (``w`` > 0, same unit as ``x``) is the radiance that maps to 1.
    """
    return _brdfpy.reinhard_extended(as_scalars("x", x), _finite("white", white))


def aces(x: ArrayLike) -> NDArray[np.float32]:
    """ACES filmic curve ``x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)``, clamped to ``[0, 1]``.

    Krzysztof Narkowicz's 2015 fit to the ACES reference rendering transform.
    """
    return _brdfpy.aces(as_scalars("x", x))


def exposure(x: ArrayLike, ev: float) -> NDArray[np.float32]:
    """Multiply linear radiance by ``2^ev`` (``ev`` in photographic stops); not clamped."""
    return _brdfpy.exposure(as_scalars("x", x), _finite("ev", ev))


def srgb_encode(x: ArrayLike) -> NDArray[np.float32]:
    """sRGB OETF (IEC 61966-2-1) after clamping to ``[0, 1]``.

    ``v = 12.92 c`` if ``c ≤ 0.0031308``, else ``v = 1.055 c^(1/2.4) − 0.055``.
    """
    return _brdfpy.srgb_encode(as_scalars("x", x))


def srgb_decode(x: ArrayLike) -> NDArray[np.float32]:
    """Inverse sRGB OETF after clamping to ``[0, 1]``.

    ``c = v / 12.92`` if ``v ≤ 0.04045``, else ``c = ((v + 0.055) / 1.055)^2.4``.
    """
    return _brdfpy.srgb_decode(as_scalars("x", x))


def to_uint8(x: ArrayLike, operator: str = "clamp", *, white: float | None = None) -> NDArray[np.uint8]:
    """Linear HDR values → 8-bit sRGB: ``floor(255 · srgb_encode(operator(x)) + 0.5)`` per channel.

    Parameters
    ----------
    x : array_like
        Linear radiance, any shape.
    operator : str
        One of :data:`OPERATORS`: ``"clamp"`` (values above 1 saturate), ``"reinhard"``,
        ``"reinhard_extended"`` (with ``white``, default 4) or ``"aces"``.
    white : float, optional
        White point of ``"reinhard_extended"``.
    """
    w = None if white is None else _finite("white", white)
    return _brdfpy.to_uint8(as_scalars("x", x), as_str("operator", operator, "an operator name"), w)
