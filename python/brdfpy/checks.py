"""BRDF properties as checks a user can run on any model (Nicodemus et al. 1977; pbrt-v4 §4.3).

A physical BRDF is non-negative, reciprocal (Helmholtz: ``f_r(l, v) = f_r(v, l)``) and conserves energy (its
directional albedo ``ρ(v) = ∫ f_r(l, v) cos θ_l dω_l`` is at most 1 for every ``v``). Every check is
deterministic: random directions come from a seeded generator and sums are added in a fixed order, so the
result is the same at any thread count.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import I64_MAX, I64_MIN, as_float, as_int, as_scalars
from brdfpy._renamed import renamed_keywords
from brdfpy.microfacet import Lobe, _lobe, _lobes
from brdfpy.models import Model
from brdfpy.sampling import AlbedoBySampling, Chi2Result, albedo_by_sampling, chi2, pdf_integral

__all__ = [
    "AlbedoBySampling",
    "CheckReport",
    "Chi2Result",
    "albedo_by_sampling",
    "check",
    "chi2",
    "d_normalization",
    "directional_albedo",
    "pdf_integral",
    "positivity",
    "reciprocity_error",
]


class CheckReport(TypedDict):
    """What :func:`check` found."""

    model: str
    physical: bool
    min_value: float
    reciprocity_error: float
    cos_theta_v: list[float]
    albedo: list[list[float]]
    max_albedo: float
    positive: bool
    reciprocal: bool
    energy_conserving: bool


def _model(model: object) -> Model:
    if not isinstance(model, _brdfpy.Model):
        raise TypeError(f"model: expected a brdfpy.Model, got {type(model).__name__}")
    return model  # type: ignore[return-value]


def _samples_seed(samples: object, seed: object) -> tuple[int, int]:
    """The sample count and seed as integers the compiled module takes (its own ranges apply after)."""
    return as_int("samples", samples, I64_MIN, I64_MAX), as_int("seed", seed, 0, I64_MAX)


@renamed_keywords(n="samples")
def reciprocity_error(model: Model, samples: int = 10000, seed: int = 0) -> float:
    """Largest relative violation of Helmholtz reciprocity over ``samples`` random configurations.

    ``max |f(l, v) − f(v, l)| / max(|f(l, v)|, |f(v, l)|, 1e-6)`` over every channel, with random unit
    normals and tangents and ``l``, ``v`` uniform over the hemisphere (seeded by ``seed``). A few float32
    ulps (≲ 1e-6) for a reciprocal model; course formulas generally are not reciprocal. NaN if the model
    returned a non-finite value.
    """
    return float(_brdfpy.reciprocity_error(_model(model), *_samples_seed(samples, seed)))


@renamed_keywords(n="samples")
def positivity(model: Model, samples: int = 10000, seed: int = 0) -> float:
    """Smallest channel of ``f_r`` [1/sr] over ``samples`` random configurations: ≥ 0 for a valid BRDF.

    NaN if the model returned a non-finite value.
    """
    return float(_brdfpy.positivity(_model(model), *_samples_seed(samples, seed)))


def directional_albedo(
    model: Model,
    cos_theta_v: ArrayLike,
    n_theta: int = 8,
    n_phi: int = 8,
    *,
    min_panel: float = 1e-4,
) -> NDArray[np.float32]:
    """Directional albedo ``ρ(v) = ∫_{H²} f_r(l, v) cos θ_l dω_l`` per RGB channel, by quadrature.

    The fraction of light arriving from ``v`` that is reflected (by reciprocity also the reflectance seen
    from ``v`` under a uniform white sky). Energy conservation requires ``ρ ≤ 1``; white Lambert gives 1.
    For a classic (course) model it is ``∫ shade dω``.

    Parameters
    ----------
    model : brdfpy.Model
    cos_theta_v : float or array_like, shape (K,)
        Cosines of the view direction's polar angle, in ``[0, 1]``; ``v = (sin θ_v, 0, cos θ_v)`` in the
        local frame (azimuth along the tangent).
    n_theta, n_phi : int
        Gauss-Legendre points per panel in θ and φ (1 to 64). The panels are graded toward the peak of the
        lobe (brdf-core ``properties``); the defaults integrate white Lambert to 1e-6 and specular lobes of
        exponent ≤ 1000 to 1e-5.
    min_panel : float
        Width [rad] of the smallest panels next to a peak (1e-9 to 0.1).

    Returns
    -------
    numpy.ndarray of float32, shape (K, 3)
    """
    c = as_scalars("cos_theta_v", cos_theta_v).reshape(-1)
    return _brdfpy.directional_albedo(
        _model(model),
        c,
        as_int("n_theta", n_theta, 1, 64),
        as_int("n_phi", n_phi, 1, 64),
        as_float("min_panel", min_panel),
    )


def d_normalization(
    distribution: str | Sequence[Lobe],
    alpha: float = 0.3,
    *,
    alpha_y: float | None = None,
    n_theta: int = 8,
    n_phi: int = 8,
    min_panel: float = 1e-4,
) -> float:
    """Normalisation of a microfacet distribution, ``∫_{H²} D(h) (n·h) dω_h``, by quadrature.

    1 for a normalised D: the microfacets' projected area equals the macro-surface's (Walter et al. 2007
    eq. 4). ``distribution`` is a name of :data:`brdfpy.microfacet.DISTRIBUTIONS` with ``alpha``
    (and ``alpha_y``), or a list of lobes as for :func:`brdfpy.microfacet.mixture`. The quadrature is graded
    toward the pole and the tangent axes; see :func:`directional_albedo` for ``n_theta``, ``n_phi`` and
    ``min_panel``.
    """
    if isinstance(distribution, str):
        lobes = _lobe(distribution, alpha, alpha_y)
    else:
        lobes = _lobes(distribution, "distribution")
    return float(
        _brdfpy.d_normalization(
            lobes,
            as_int("n_theta", n_theta, 1, 64),
            as_int("n_phi", n_phi, 1, 64),
            as_float("min_panel", min_panel),
        )
    )


def check(model: Model) -> CheckReport:
    """All checks with fixed settings: positivity and reciprocity over 10 000 configurations (seed 0), and
    the directional albedo at six view cosines.

    Returns
    -------
    dict
        ``model``, ``physical``, ``min_value``, ``reciprocity_error``, ``cos_theta_v``, ``albedo`` (one
        RGB per cosine), ``max_albedo`` and the verdicts ``positive``, ``reciprocal`` (error ≤ 1e-4) and
        ``energy_conserving`` (albedo ≤ 1 + 1e-4). The verdicts are meaningful for physical models.
    """
    report: CheckReport = _brdfpy.check(_model(model))  # type: ignore[assignment]
    return report
