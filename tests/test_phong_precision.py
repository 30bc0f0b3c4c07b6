"""The Phong-family specular power ``max(r·v, 0)^γ`` stays at float32's floor where it is hardest: near
the normal, near the mirror direction (also at grazing), with exponents up to 10 000 (Phong) and 30 000
(Strauss), where a relative error ``e`` of the base becomes ``γ e`` of the value.

The reference is the float64 oracle on the exact (float64) directions; brdfpy gets them rounded to
float32. Two things bound what float32 can do:

* the rounding of the inputs: the oracle on the float32-rounded directions moves by ``floor`` (one
  realisation per sample);
* float32 arithmetic on unit vectors moves ``r·v`` by a few ulps (2^-24) of the size of its gradient,
  ``σ = |r - v| + |(n·v) l_perp + (n·l) v_perp|`` (the l and v gradients are ``sin∠(r, v) <= |r - v|``,
  the n gradient is twice the second term; all vanish at the mirror direction, where the lobe is
  flat), which ``x^γ`` turns into ``γ σ/(r·v)`` relative; the power itself, evaluated as
  ``exp(γ ln(1 - d))``, costs a few ulps of ``1 + |ln (r·v)^γ|``. Strauss's ``r_j`` reads
  the angles of l and v to n; float32 gets them to a few 2^-24 rad (as ``atan2(|n×w|, n·w)``;
  ``acos(n·w)`` was 180 times the floor near the normal), which costs
  ``S_rj = |∂ ln r_j/∂θ_l| + |∂ ln r_j/∂θ_v|`` ulps.

So each sample must match to ``4 floor + 4·2^-24 (2 + γ |ln r·v| + γ σ/(r·v) + S_rj)`` (relative).
Measured: at most 0.48 of that for phong and phong_classic (γ = 1 anywhere above the surface; 0.25 at
γ = 10 000, 6.9e-5 relative where the floor reaches 4.7e-5), 0.65 for Strauss (at grazing, where its
shadow curve G is a float32 difference of two numbers near 10^4). The former base
``r·v = 2(n·l)(n·v) - l·v`` (Strauss: ``(2(n·l)n - l)·v``) fails it: it rounds ``r·v ≈ 1`` to float32
(from ``≈ 2`` minus ``≈ 1`` near the normal), an absolute error of a few 2^-24 that does not shrink at
the peak. A float32 NumPy emulation of it reaches 7 500 times the bound at γ = 10 000 (7.0e-3 relative
where the floor is 4.6e-5), 14 times at γ = 10 and 1.4 at γ = 1; ``(n·l)(n·v) - l_perp·v_perp`` cancels
less but still rounds a number near 1 (3 500 times), and ``(1 - d)^γ`` with the deficit below rounded
back to ``1 - d`` 270 times. brdfpy computes the deficit ``d = 1 - r·v = (|l_perp + v_perp|^2 +
(n·l - n·v)^2)/2`` from differences that are small where the lobe is, and ``(1 - d)^γ`` as
``exp(γ ln1p(-d))``: at most 0.53 of the bound in the same emulation.
"""

from __future__ import annotations

import dataclasses

import brdfpy
import numpy as np
import pytest

from conftest import F32_ULP, direction, in_random_frame, log_uniform, unit
from oracle import models as om

ULP = F32_ULP
COUNT = 20000


def _adversarial(rng: np.random.Generator, family: str) -> dict[str, np.ndarray]:
    """Float64 l, v (both above the surface) and n, built in a local frame and turned to a random
    world frame."""
    phi = rng.uniform(0, 2 * np.pi, COUNT)
    if family == "near_normal":  # both within 1e-5 .. 0.05 rad of the normal
        l = direction(np.cos(log_uniform(rng, 1e-5, 0.05, COUNT)), phi)
        v = direction(np.cos(log_uniform(rng, 1e-5, 0.05, COUNT)), rng.uniform(0, 2 * np.pi, COUNT))
    elif family == "wide":  # anywhere above the surface
        l = direction(rng.uniform(1e-3, 1, COUNT), phi)
        v = direction(rng.uniform(1e-3, 1, COUNT), rng.uniform(0, 2 * np.pi, COUNT))
    else:  # v within 1e-7 .. 0.2 rad of the mirror direction of l
        grazing = family.endswith("grazing")
        cos_l = log_uniform(rng, 1e-4, 0.1, COUNT) if grazing else rng.uniform(1e-3, 1, COUNT)
        l = direction(cos_l, phi)
        mirror = l * [-1.0, -1.0, 1.0]
        axis = unit(np.cross(mirror, rng.normal(size=mirror.shape)))
        turn = log_uniform(rng, 1e-7, 0.2, COUNT)[:, None]
        v = mirror * np.cos(turn) + axis * np.sin(turn)
    g = in_random_frame(rng, l, v)
    del g["tangent"]
    return g


def _strauss_rj_sensitivity(g: om.Geo, params: dict) -> np.ndarray:
    """``|∂ ln r_j/∂θ_l| + |∂ ln r_j/∂θ_v|`` of the oracle [1/rad], by central differences in the angles.
    Only r_j reads g.nl and g.nv (the specular base reads the vectors; the parameters make Q_d = 0)."""
    kwargs = {om.MODELS["strauss"][2].get(k, k): p for k, p in params.items() if k != "base_color"}

    def log_q(theta_l: np.ndarray, theta_v: np.ndarray) -> np.ndarray:
        moved = dataclasses.replace(g, nl=np.cos(theta_l), nv=np.cos(theta_v))
        return np.log(om.strauss(moved, color_=params["base_color"], **kwargs)[:, 0])

    theta_l, theta_v, h = np.arccos(g.nl), np.arccos(g.nv), 1e-7
    with np.errstate(all="ignore"):
        dl = (log_q(theta_l + h, theta_v) - log_q(theta_l - h, theta_v)) / (2 * h)
        dv = (log_q(theta_l, theta_v + h) - log_q(theta_l, theta_v - h)) / (2 * h)
    return np.abs(dl) + np.abs(dv)


#: Strauss's constants as brdfpy holds them (float32); its shadow curve is steep at grazing.
K32 = {
    k: float(np.float32(c)) for k, c in {"k_fresnel": 1.12, "k_shadow": 1.01, "k_offspecular": 0.1}.items()
}

#: (model, parameters with only the specular lobe, its exponent, quantity compared).
CASES = [
    *[("phong", {"kd": 0.0, "ks": 1.0, "shininess": s}, s, "eval") for s in (1.0, 30.0, 1000.0, 10000.0)],
    *[("phong_classic", {"kd": 0.0, "ks": 1.0, "shininess": s}, s, "shade") for s in (10.0, 10000.0)],
    *[
        # brdfpy holds the smoothness in float32: the oracle gets that value (h = 3/(1 - s) is steep).
        (
            "strauss",
            {
                "base_color": 0.0,
                "smoothness": float(np.float32(s)),
                "metalness": 0.0,
                "transparency": 0.0,
                **K32,
            },
            3 / (1 - float(np.float32(s))),
            "shade",
        )
        for s in (0.7, 0.99, 0.9999)
    ],
]
FAMILIES = ["near_normal", "mirror", "mirror_grazing", "wide"]
# Anywhere above the surface, a lobe of exponent above 1000 holds too few samples to say anything.
GRID = [(*case, family) for case in CASES for family in FAMILIES if family != "wide" or case[2] <= 1000]


@pytest.mark.parametrize(
    ("name", "params", "gamma", "quantity", "family"),
    GRID,
    ids=[f"{c[0]}-{c[2]:g}-{c[4]}" for c in GRID],
)
def test_specular_power_stays_at_the_float32_floor_in_adversarial_geometry(
    name: str, params: dict, gamma: float, quantity: str, family: str
) -> None:
    rng = np.random.default_rng(sum(f"{name}/{gamma}/{family}".encode()))
    g64 = _adversarial(rng, family)
    g32 = {k: a.astype(np.float32) for k, a in g64.items()}
    want = om.evaluate(name, params, **g64, quantity=quantity)[:, 0]
    rounded = om.evaluate(
        name, params, **{k: a.astype(np.float64) for k, a in g32.items()}, quantity=quantity
    )
    rounded = rounded[:, 0]
    model = brdfpy.model(name, **params)
    got = (model.eval if quantity == "eval" else model.shade)(**g32)[:, 0].astype(np.float64)
    # Samples that matter: within 1e-6 of the family's largest value, and far from float32's underflow.
    compared = (want > 1e-6 * want.max()) & (want > 1e-30)
    assert compared.sum() >= 100, f"only {compared.sum()} samples inside the lobe"
    geo = om.geometry(g64["l"], g64["v"], g64["n"])
    lp = geo.l - geo.nl[:, None] * geo.n
    vp = geo.v - geo.nv[:, None] * geo.n
    r = 2 * geo.nl[:, None] * geo.n - geo.l
    rv = np.sum(r * geo.v, axis=-1)
    sigma = np.linalg.norm(r - geo.v, axis=-1) + np.linalg.norm(
        geo.nv[:, None] * lp + geo.nl[:, None] * vp, axis=-1
    )
    with np.errstate(all="ignore"):  # rv <= 0 only where want = 0, which is not compared
        sensitivity = 2 + gamma * np.abs(np.log(rv)) + gamma * sigma / rv
    if name == "strauss":
        sensitivity = sensitivity + _strauss_rj_sensitivity(geo, params)
    want, rounded, got, sensitivity = want[compared], rounded[compared], got[compared], sensitivity[compared]
    floor = np.abs(rounded - want) / want
    bound = 4 * floor + 4 * ULP * sensitivity
    err = np.abs(got - want) / want
    worst = int(np.argmax(err / bound))
    assert np.all(err <= bound), (
        f"{np.sum(err > bound)} of {err.size} samples off; worst: relative error {err[worst]:.3g}, "
        f"floor {floor[worst]:.3g}, bound {bound[worst]:.3g}"
    )
