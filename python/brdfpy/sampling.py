"""Importance sampling: the samplers behind :meth:`brdfpy.Model.sample` and the checks that test them.

Every model draws light directions ``l`` for a view ``v`` roughly in proportion to ``f_r(l, v) cos θ_l`` and
reports the density it draws them with (per steradian), so a Monte Carlo estimate of the reflected radiance
``L_o(v) = ∫ f_r(l, v) cos θ_l L_i(l) dω_l`` is the mean of ``weight · L_i(l)`` (pbrt-v4, Pharr, Jakob &
Humphreys, "Physically Based Rendering", 4th ed., ch. 9). The techniques, one per lobe, are documented in
the README ("Sampling") and in brdf-core's ``sampling`` module: cosine-weighted hemisphere (Lambert,
Oren-Nayar, diffuse terms), Phong and Lafortune cosine-power lobes, Blinn-Phong half vectors, visible
normals of GGX (Heitz 2018) and Beckmann (Heitz & d'Eon 2014; Jakob 2014), Ward's (Ward 1992; Walter 2005)
and Ashikhmin & Shirley's (2000) samplers, a tabulated sampler for measured tables, and lobe selection by
estimated albedo for sums.

This module holds the counter-based random numbers (:func:`uniform`) and the three checks
(:func:`chi2`, :func:`pdf_integral`, :func:`albedo_by_sampling`, also in :mod:`brdfpy.checks`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import as_float, as_int, as_scalars, as_vec3
from brdfpy._renamed import renamed_keywords

__all__ = ["AlbedoBySampling", "Chi2Result", "albedo_by_sampling", "chi2", "pdf_integral", "uniform"]

F32 = NDArray[np.float32]

#: What :meth:`brdfpy.Model.sample` returns and a custom ``sample`` passed to :func:`chi2` must return.
SampleFn = Callable[..., tuple[F32, F32, F32]]
#: What :meth:`brdfpy.Model.pdf` is and a custom ``pdf`` passed to :func:`chi2` must be.
PdfFn = Callable[..., F32]


def _int(name: str, x: object, lo: int, hi: int) -> int:
    if isinstance(x, bool) or not isinstance(x, (int, np.integer)):
        raise TypeError(f"{name}: expected an integer, got {type(x).__name__}")
    k = int(x)
    if not lo <= k <= hi:
        raise ValueError(f"{name}: expected an integer in [{lo}, {hi}], got {k}")
    return k


def _model(model: object) -> Any:
    if not isinstance(model, _brdfpy.Model):
        raise TypeError(f"model: expected a brdfpy.Model, got {type(model).__name__}")
    return model


def seed_arg(seed: object) -> int:
    """Validate a seed: an integer in ``[0, 2**64)``."""
    return _int("seed", seed, 0, 2**64 - 1)


def count_arg(name: str, count: object) -> int:
    """Validate a sample count: an integer in ``[1, 2**26]`` (the compiled module's limit)."""
    return _int(name, count, 1, 2**26)


def uniform(count: int, seed: int = 0) -> F32:
    """The uniform numbers ``u`` that :meth:`brdfpy.Model.sample` uses when it is given none.

    Row ``i`` is a pure function of ``(seed, i)``: the ``(3 i + d)``-th output of SplitMix64 (Steele, Lea &
    Flood 2014) started from the state ``mix(seed)``, top 24 bits, so every value is a multiple of 2⁻²⁴ in
    ``[0, 1)``. Results therefore do not depend on how a batch is split into threads.

    Returns
    -------
    numpy.ndarray of float32, shape (count, 3)
        Column 0 selects a lobe, columns 1 and 2 drive the direction.
    """
    return _brdfpy.uniform(count_arg("count", count), seed_arg(seed))


def _one_vec3(name: str, x: ArrayLike) -> F32:
    a, single = as_vec3(name, x)
    if not single and a.shape[0] != 1:
        raise ValueError(f"{name}: expected one direction, shape (3,), got {a.shape}")
    if not np.all(np.isfinite(a)) or not np.any(a):
        raise ValueError(f"{name}: must be a finite, non-zero vector, got {a.reshape(3).tolist()}")
    return a.reshape(3)


class Chi2Result(TypedDict):
    """What :func:`chi2` found."""

    passed: bool
    p_value: float
    significance: float
    statistic: float
    dof: int
    sample_fraction: float
    pdf_integral: float
    pooled_cells: int
    pooled_groups: int
    problems: list[str]
    observed: NDArray[np.float64]
    expected: NDArray[np.float64]


def _short(x: object) -> str:
    r = repr(x)
    return r if len(r) <= 80 else r[:80] + "..."


def _returned(name: str, x: object, what: str) -> F32:
    """What a user's callable ``name`` returned, as float32; a ``TypeError`` naming it otherwise."""
    try:
        with np.errstate(over="ignore", invalid="ignore"):
            a = np.asarray(x, dtype=np.float32)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected the callable to return {what}, got {_short(x)}") from None
    return a


@renamed_keywords(sample_count="samples")
def chi2(
    model: Any,
    v: ArrayLike,
    n: ArrayLike = (0.0, 0.0, 1.0),
    *,
    tangent: ArrayLike | None = None,
    samples: int = 1_000_000,
    seed: int = 0,
    n_theta: int = 64,
    n_phi: int = 128,
    zoom: float = 1.0,
    ires: int = 6,
    peak: ArrayLike | None = None,
    significance: float = 0.01,
    test_count: int = 1,
    sample: SampleFn | None = None,
    pdf: PdfFn | None = None,
) -> Chi2Result:
    """Pearson's χ² goodness-of-fit test of a model's sampler against the density it reports.

    In the style of Mitsuba 3's ``mi.chi2.ChiSquareTest``: draw ``samples`` directions for view ``v``
    with ``model.sample``, count the valid ones (``pdf > 0``) in the cells of a grid over the hemisphere, and
    compare with the expected counts ``E_i = N ∫_cell pdf dω``, integrated with ``ires × ires``
    Gauss-Legendre points per cell from ``model.pdf``. Cells with ``E_i ≥ 5`` each add ``(O_i − E_i)²/E_i``;
    smaller ones are pooled in increasing ``E_i`` until ``ΣE ≥ 5`` (Cochran 1954). The p-value is the χ²
    tail probability for (terms − 1) degrees of freedom.

    **What a pass means.** A correct sampler passes with probability ``1 − significance``: its p-values are
    uniform on [0, 1]. A sampler whose distribution differs from its reported density by more than the noise
    of ``samples`` samples fails (e.g. a GGX lobe drawn at roughness 0.3 and reported at 0.36). With
    ``test_count = k`` the threshold is Šidák-corrected, ``1 − (1 − significance)^(1/k)``, so that ``k``
    correct tests all pass with probability ``1 − significance``. Samples in a cell whose expected count is
    exactly 0 (or a density integrating above 1.1) fail outright (``problems``).

    Parameters
    ----------
    model : brdfpy.Model
    v, n : array_like, shape (3,)
        View direction and normal (world space, need not be unit).
    tangent : array_like, shape (3,), optional
        First tangent (anisotropic models); also the φ = 0 axis of the grid.
    samples, seed : int
        Samples drawn and the seed of their random numbers (:func:`uniform`).
    n_theta, n_phi : int
        Cells in ``y = 1 − cos θ`` (1 to 4096) and in φ (1 to 8192).
    zoom : float
        Grading of the cells toward ``peak`` (1 to 16): 1 is uniform in ``cos θ`` and φ (equal solid angle,
        Mitsuba's grid); ``k`` packs cells toward the peak as the ``k``-th power of the distance, which
        resolves lobes down to roughness ~1e-3. The horizon and the peak are always cell edges.
    ires : int
        Gauss-Legendre points per cell and axis (1 to 16).
    peak : array_like, shape (3,), optional
        Direction the grid is graded toward; default the mirror direction of ``v``.
    significance, test_count : float, int
        See above.
    sample, pdf : callable, optional
        Replace ``model.sample`` (called as ``sample(v, n, seed=..., tangent=..., count=...)`` and returning
        ``(l, weight, pdf)``) or ``model.pdf`` (called as ``pdf(l, v, n, tangent)``): to test another sampler
        against this model's density, or to check that the test rejects a wrong one.

    Returns
    -------
    dict
        ``passed``, ``p_value``, ``significance`` (after the correction), ``statistic``, ``dof``,
        ``sample_fraction`` (valid samples / N), ``pdf_integral`` (``Σ E_i / N``), ``pooled_cells``,
        ``pooled_groups``, ``problems`` and the per-cell ``observed`` and ``expected`` counts (the last cell
        is everything at or below the horizon).
    """
    vv, nn = _one_vec3("v", v), _one_vec3("n", n)
    tt = None if tangent is None else _one_vec3("tangent", tangent)
    count = count_arg("samples", samples)
    if not 0.0 < as_float("significance", significance) < 1.0:
        raise ValueError(f"significance: expected a number in (0, 1), got {significance}")
    tests = count_arg("test_count", test_count)
    for name, fn in (("sample", sample), ("pdf", pdf)):
        if fn is None:
            _model(model)  # the model's own sampler or density is used
        elif not callable(fn):
            raise TypeError(f"{name}: expected a callable, got {type(fn).__name__}")
    draw: SampleFn = model.sample if sample is None else sample
    density: PdfFn = model.pdf if pdf is None else pdf
    drawn = draw(vv, nn, seed=seed_arg(seed), tangent=tt, count=count)
    if not isinstance(drawn, tuple) or len(drawn) != 3:
        raise TypeError(f"sample: expected the callable to return (l, value, pdf), got {_short(drawn)}")
    l_rows = _returned("sample", drawn[0], "directions l of shape (count, 3)").reshape(-1, 3)
    p_rows = _returned("sample", drawn[2], "densities of shape (count,)").reshape(-1)
    if len(p_rows) != len(l_rows):
        raise ValueError(f"sample: returned {len(l_rows)} directions but {len(p_rows)} densities")
    valid = np.ascontiguousarray(l_rows[p_rows > 0])
    if peak is None:
        vu, nu = vv / np.linalg.norm(vv), nn / np.linalg.norm(nn)
        pk = (2.0 * np.dot(nu, vu) * nu - vu).astype(np.float32)
    else:
        pk = _one_vec3("peak", peak)

    def claimed(points: F32) -> F32:
        d = _returned("pdf", density(points, vv, nn, tt), "densities, one per direction")
        return np.ascontiguousarray(d.reshape(-1))

    r = _brdfpy.chi2_test(
        valid,
        count,
        claimed,
        nn,
        pk,
        tt,
        as_int("n_theta", n_theta, 1, 4096),
        as_int("n_phi", n_phi, 1, 4096),
        as_float("zoom", zoom),
        as_int("ires", ires, 1, 64),
    )
    alpha = 1.0 - (1.0 - float(significance)) ** (1.0 / tests)
    p_value = float(r["p_value"])
    result: Chi2Result = {
        "passed": not r["problems"] and np.isfinite(p_value) and p_value >= alpha,
        "p_value": p_value,
        "significance": alpha,
        "statistic": float(r["statistic"]),
        "dof": int(r["dof"]),
        "sample_fraction": float(r["sample_fraction"]),
        "pdf_integral": float(r["pdf_integral"]),
        "pooled_cells": int(r["pooled_cells"]),
        "pooled_groups": int(r["pooled_groups"]),
        "problems": list(r["problems"]),
        "observed": r["observed"],
        "expected": r["expected"],
    }
    return result


def pdf_integral(
    model: Any,
    cos_theta_v: ArrayLike,
    n_theta: int = 16,
    n_phi: int = 16,
    *,
    min_panel: float = 1e-4,
) -> NDArray[np.float64]:
    """``∫_{H²} pdf(l, v) dω_l`` over the upper hemisphere, by quadrature, at each view cosine.

    The view is ``v = (sin θ_v, 0, cos θ_v)`` with ``n = z`` and tangent ``x``; the quadrature is the graded
    Gauss-Legendre product rule of :func:`brdfpy.checks.directional_albedo` (``n_theta``, ``n_phi`` and
    ``min_panel`` as there), graded toward the mirror direction. The defaults take twice its points per
    panel: an anisotropic lobe at normal view (Ward, αx = 0.04, αy = 0.4) is 5e-4 off with 8 × 8 and within
    1e-6 of the converged value with 16 × 16.

    **What it means.** 1 for a sampler that never fails (cosine-weighted lobes); below 1 by exactly the
    probability that a sample fails (a glossy lobe drawn partly below the horizon returns ``pdf = 0``), which
    :func:`albedo_by_sampling`'s ``valid_fraction`` estimates. Above 1 is a bug.

    Returns
    -------
    numpy.ndarray of float64, shape (K,)
    """
    c = as_scalars("cos_theta_v", cos_theta_v).reshape(-1)
    return _brdfpy.pdf_integral(
        _model(model),
        c,
        as_int("n_theta", n_theta, 1, 64),
        as_int("n_phi", n_phi, 1, 64),
        as_float("min_panel", min_panel),
    )


class AlbedoBySampling(TypedDict):
    """What :func:`albedo_by_sampling` estimates."""

    albedo: NDArray[np.float64]
    std_error: NDArray[np.float64]
    valid_fraction: NDArray[np.float64]


@renamed_keywords(n_samples="samples")
def albedo_by_sampling(
    model: Any, cos_theta_v: ArrayLike, samples: int = 1 << 16, *, seed: int = 0
) -> AlbedoBySampling:
    """Directional albedo ``ρ(v) = ∫ f_r(l, v) cos θ_l dω_l`` by Monte Carlo with the model's own sampler.

    ``ρ ≈ mean(weight)`` over ``samples`` samples of :meth:`brdfpy.Model.sample` at ``v = (sin θ_v, 0,
    cos θ_v)``, ``n = z``, tangent ``x`` (failed samples count with weight 0), with the standard error
    ``std(weight)/√samples``. For a classic (course) model the weight is ``shade/pdf`` and the estimate is
    ``∫ shade dω``, as for :func:`brdfpy.checks.directional_albedo`.

    **What it means.** An unbiased sampler's estimate agrees with the quadrature albedo
    (:func:`brdfpy.checks.directional_albedo`) within a few standard errors; a sampler that misses part of
    the lobe (zero density where ``f_r > 0``) comes out low, one whose weights disagree with its density
    comes out wrong either way. A small standard error means the sampler matches ``f_r cos θ`` well
    (importance sampling Lambert this way has zero variance).

    Returns
    -------
    dict
        ``albedo`` and ``std_error`` of shape (K, 3) and ``valid_fraction`` (K,), float64.
    """
    model = _model(model)
    c = as_scalars("cos_theta_v", cos_theta_v).reshape(-1).astype(np.float64)
    if c.size == 0 or not np.all((c > 0.0) & (c <= 1.0)):
        raise ValueError(f"cos_theta_v: values must lie in (0, 1], got {c.tolist()}")
    count = count_arg("samples", samples)
    s = seed_arg(seed)
    mean, err, valid = (np.empty((c.size, 3)), np.empty((c.size, 3)), np.empty(c.size))
    for k, ct in enumerate(c):
        v = np.array([np.sqrt(max(0.0, 1.0 - ct * ct)), 0.0, ct], dtype=np.float32)
        _, w, p = model.sample(v, (0.0, 0.0, 1.0), seed=s, tangent=(1.0, 0.0, 0.0), count=count)
        w64 = np.asarray(w, dtype=np.float64)
        mean[k] = w64.mean(axis=0)
        err[k] = w64.std(axis=0, ddof=1) / np.sqrt(count) if count > 1 else np.inf
        valid[k] = float(np.count_nonzero(np.asarray(p) > 0)) / count
    return {"albedo": mean, "std_error": err, "valid_fraction": valid}
