"""Reflection, refraction and the half vector over batches of directions.

Every direction points away from the surface (the convention of the whole package): ``w`` and the result of
:func:`reflect` are both on the side the normal points to. Inputs are array-likes of shape ``(N, 3)`` or
``(3,)``, broadcast against each other; outputs are float32 ``(N, 3)``, or ``(3,)`` when every input was
``(3,)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import as_scalars, as_vec3_args

__all__ = ["halfway", "reflect", "refract"]


def reflect(w: ArrayLike, n: ArrayLike) -> NDArray[np.float32]:
    """Mirror direction of ``w`` about the normal: ``r = 2(n̂·w)n̂ − w`` with ``n̂ = n/|n|`` (seed 003).

    ``w`` keeps its length (a unit ``w`` gives a unit ``r``); a zero-length ``n`` gives 0.
    """
    (wa, na), single = as_vec3_args(w=w, n=n)
    assert wa is not None and na is not None
    out = _brdfpy.reflect(wa, na)
    return out.reshape(3) if single else out


def halfway(l: ArrayLike, v: ArrayLike) -> NDArray[np.float32]:
    """Unit half vector ``h = (l̂ + v̂)/|l̂ + v̂|`` (Blinn 1977).

    0 where ``l̂ = −v̂`` or an input has zero length.
    """
    (la, va), single = as_vec3_args(l=l, v=v)
    assert la is not None and va is not None
    out = _brdfpy.halfway(la, va)
    return out.reshape(3) if single else out


def refract(w: ArrayLike, n: ArrayLike, eta: ArrayLike) -> tuple[NDArray[np.float32], NDArray[np.bool_]]:
    """Refracted direction by Snell's law, ``η_i sin θ_i = η_t sin θ_t`` (seed 001).

    Parameters
    ----------
    w : array_like, shape (N, 3) or (3,)
        Direction toward where the light comes from, on the side ``n`` points to (normalised here).
    n : array_like, shape (N, 3) or (3,)
        Surface normal (normalised here).
    eta : float or array_like, shape (N,)
        Relative index of refraction ``η_t / η_i`` (> 0), e.g. 1.5 from air into glass.

    Returns
    -------
    t : numpy.ndarray of float32, shape (N, 3) or (3,)
        Unit transmitted direction, pointing away from the surface on the far side:
        ``t = −w/η + (cos θ_i/η − cos θ_t) n`` with ``cos θ_t = sqrt(1 − sin²θ_i/η²)``.
    ok : numpy.ndarray of bool, shape (N,) or ()
        ``False`` (and ``t = 0``) on total internal reflection (``sin θ_i > η``), when ``w`` is below the
        surface, or for a zero-length input.
    """
    (wa, na), single = as_vec3_args(w=w, n=n)
    assert wa is not None and na is not None
    e = as_scalars("eta", eta)
    if e.ndim > 1:
        raise ValueError(f"eta: expected a number or shape (N,), got {e.shape}")
    single = single and e.ndim == 0
    t, ok = _brdfpy.refract(wa, na, e.reshape(-1))
    return (t.reshape(3), ok.reshape(())) if single else (t, ok)
