"""Clamping and HDR tone mapping (seed 000 "clamp vs HDR"), float64.

Sources: seed 000 (clamp), Reinhard et al. 2002 "Photographic Tone Reproduction for Digital Images"
(eqs. 3 and 4), Narkowicz 2015 "ACES Filmic Tone Mapping Curve" (the fitted rational curve),
IEC 61966-2-1 (sRGB transfer functions), SCENE.md (8-bit quantisation ``floor(255 v + 0.5)``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]


def clamp(x: ArrayLike) -> F64:
    """Seed 000: 0 below 0, 1 above 1, identity in between."""
    return np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)


def reinhard(x: ArrayLike) -> F64:
    """Reinhard 2002 eq. 3: ``x / (1 + x)`` (negative input clamped to 0 first)."""
    x = np.maximum(np.asarray(x, dtype=np.float64), 0.0)
    return x / (1.0 + x)


def reinhard_extended(x: ArrayLike, white: float) -> F64:
    """Reinhard 2002 eq. 4: ``x (1 + x/white^2) / (1 + x)``; maps ``white`` to exactly 1, and what is
    brighter burns out to 1 ("L_white is the smallest luminance mapped to pure white")."""
    x = np.maximum(np.asarray(x, dtype=np.float64), 0.0)
    return np.minimum(x * (1.0 + x / (white * white)) / (1.0 + x), 1.0)


def aces(x: ArrayLike) -> F64:
    """Narkowicz 2015 ACES fit ``x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)``, clamped to [0, 1]."""
    x = np.maximum(np.asarray(x, dtype=np.float64), 0.0)
    return np.clip(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0)


def exposure(x: ArrayLike, ev: float) -> F64:
    """Photographic exposure: multiply by ``2^ev``."""
    return np.asarray(x, dtype=np.float64) * 2.0**ev


def srgb_encode(x: ArrayLike) -> F64:
    """sRGB OETF: ``12.92 c`` for ``c <= 0.0031308`` else ``1.055 c^(1/2.4) - 0.055`` (c clamped to [0,1])."""
    c = np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1.0 / 2.4) - 0.055)


def srgb_decode(x: ArrayLike) -> F64:
    """Inverse sRGB: ``v/12.92`` for ``v <= 0.04045`` else ``((v + 0.055)/1.055)^2.4``."""
    v = np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def to_uint8(x: ArrayLike, operator: str = "clamp") -> NDArray[np.uint8]:
    """Tone map with ``operator``, sRGB-encode, quantise with ``floor(255 v + 0.5)`` (SCENE.md)."""
    ops = {"clamp": clamp, "reinhard": reinhard, "aces": aces}
    v = srgb_encode(ops[operator](x))
    return np.floor(255.0 * v + 0.5).astype(np.uint8)
