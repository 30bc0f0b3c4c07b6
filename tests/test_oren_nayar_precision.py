"""Oren-Nayar (qualitative and full) stays at float32's floor where its angular terms are hardest to get
right: directions near the normal, one near the normal and the other far from it, near grazing, with the
light and the viewer in the same, the opposite or any azimuth, for roughness sigma from 0.05 to pi/2.

The reference is the float64 oracle on the exact (float64) directions; brdfpy gets them rounded to
float32. Errors are measured against ``M``, the sum of the magnitudes of the model's terms (for the
qualitative model, the value itself): at grazing, opposite azimuths and large sigma the full model's
``C2`` term, ``-|cos dphi| C2 tan(beta)``, nearly cancels ``C1`` and the value crosses zero (down to
-0.007 M in the oracle), so a relative error of the value means nothing there. Two things bound what
float32 can do:

* the rounding of the inputs: the oracle on the float32-rounded directions moves by ``floor``
  (one realisation per sample);
* float32 arithmetic: a few ulps (2^-24) of ``M``, plus the few ulps of angle by which normalising and
  projecting the float32 directions turns them (2^-24 rad of theta_i, theta_r; 2^-24/sin(theta) of
  each azimuth), which cost ``S = |df/dtheta_i| + |df/dtheta_r| + |df/ddphi| (1/sin theta_i +
  1/sin theta_r)`` ulps (large at grazing, where ``tan(beta)`` grows like ``1/cos(theta)``).

So each sample must match to ``4 floor + 2^-24 (6 + 4 S/M)`` (in units of M; the 6 ulps are the
float32 constants, 1/pi alone is 0.68 ulp off, and the half-dozen roundings of the final sums).
Measured: at most 0.61 of that (the full model at sigma = 0.05, 3.7 ulps anywhere above the surface;
0.45 at sigma = pi/2), the qualitative model 0.39. The former cosine forms of the full model fail it
in 50 of the 60 cases, by up to 940 times (a float32 NumPy emulation of them, which reproduced the
library's errors before the change): ``sin(theta) = sqrt(1 - cos^2)`` and ``theta = acos(cos)`` of a
float32 cosine near 1 (``beta = 0`` below 2.4e-4 rad), ``cos dphi = (l.v - (n.l)(n.v))/(sin sin)``,
``1 - |cos dphi|`` and ``sin(alpha) - (2 beta/pi)^3`` (two numbers near 1 at grazing) left 6 700 ulps
of M with l near the normal and v far from it (floor 0.7; now 2.9), 285 with both near the normal
(floor 0.03; now 2.5) and 9 000 at grazing in opposite azimuths (floor 4.7; now 7.7). The qualitative
model's ``l.v - (n.l)(n.v)`` cancels near the normal too, but there it only enters
``B max(0, s)/cos(beta)`` with ``s`` small: it cost at most 5.9 ulps of the value (floor 0.06), 1.9
with ``s = l_perp . v_perp`` from components, both inside the arithmetic allowance above, so this
test does not tell those two apart.
"""

from __future__ import annotations

import brdfpy
import numpy as np
import pytest

from conftest import F32_ULP, log_uniform
from oracle import models as om

ULP = F32_ULP
COUNT = 20000
HALF_PI = np.pi / 2


def _local(theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1)


def _angles(rng: np.random.Generator, family: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """theta_i, theta_r and dphi of a family "<polar>/<azimuth>"; the polar pair in random order."""
    polar, azimuth = family.split("/")
    near = log_uniform(rng, 1e-5, 0.05, COUNT)  # within 1e-5 .. 0.05 rad of the normal
    grazing = HALF_PI - log_uniform(rng, 1e-4, 0.1, COUNT)  # within 1e-4 .. 0.1 rad of the horizon
    anywhere = np.arccos(rng.uniform(1e-3, 1, COUNT))
    first, second = {
        "near_normal": (near, log_uniform(rng, 1e-5, 0.05, COUNT)),
        "normal_far": (near, anywhere),
        "grazing": (grazing, HALF_PI - log_uniform(rng, 1e-4, 0.1, COUNT)),
        "grazing_far": (grazing, anywhere),
        "wide": (anywhere, np.arccos(rng.uniform(1e-3, 1, COUNT))),
    }[polar]
    swap = rng.random(COUNT) < 0.5
    jitter = rng.normal(0.0, 1e-3, COUNT)
    dphi = {"same": jitter, "opposite": np.pi + jitter, "any": rng.uniform(0, 2 * np.pi, COUNT)}[azimuth]
    return np.where(swap, second, first), np.where(swap, first, second), dphi


def _world(rng: np.random.Generator, theta_i: np.ndarray, theta_r: np.ndarray, dphi: np.ndarray) -> dict:
    """Float64 l, v, n: the local directions (azimuth of l random) turned to a random world frame."""
    phi = rng.uniform(0, 2 * np.pi, COUNT)
    n = rng.normal(size=(COUNT, 3))
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    t = np.cross(n, rng.normal(size=(COUNT, 3)))
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    b = np.cross(n, t)

    def world(w: np.ndarray) -> np.ndarray:
        return w[:, :1] * t + w[:, 1:2] * b + w[:, 2:3] * n

    return {"l": world(_local(theta_i, phi)), "v": world(_local(theta_r, phi + dphi)), "n": n}


def _local_oracle(name: str, params: dict, theta_i: np.ndarray, theta_r: np.ndarray, dphi: np.ndarray):
    """The oracle at the angles themselves (n = z), for derivatives in them."""
    zero = np.zeros_like(theta_i)
    return om.evaluate(name, params, _local(theta_i, zero), _local(theta_r, dphi), [0.0, 0.0, 1.0])[:, 0]


def _terms(name: str, params: dict, theta_i: np.ndarray, theta_r: np.ndarray, dphi: np.ndarray):
    """M: the sum of the magnitudes of the model's terms, as the oracle defines them."""
    s2 = params["sigma"] ** 2
    rho = params["kd"]
    alpha, beta = np.maximum(theta_i, theta_r), np.minimum(theta_i, theta_r)
    cd = np.cos(dphi)
    if name == "oren_nayar":
        c = {"qualitative": 0.33, "compensated": 0.57}[params["variant"]]
        a, bb = 1 - 0.5 * s2 / (s2 + c), 0.45 * s2 / (s2 + 0.09)
        return rho / np.pi * (a + bb * np.maximum(cd, 0) * np.sin(alpha) * np.tan(beta))
    k = s2 / (s2 + 0.09)
    w = 2 * beta / np.pi
    c2 = 0.45 * k * np.where(cd >= 0, np.sin(alpha), np.sin(alpha) - w**3)
    c3 = 0.125 * k * (4 * alpha * beta / np.pi**2) ** 2
    l1 = 1 - 0.5 * s2 / (s2 + 0.33) + np.abs(cd * c2 * np.tan(beta))
    l1 = l1 + (1 - np.abs(cd)) * c3 * np.tan(0.5 * (alpha + beta))
    l2 = 0.17 * rho * s2 / (s2 + 0.13) * (1 + np.abs(cd) * w**2) if params["interreflection"] else 0.0
    return rho / np.pi * (l1 + l2)


def _f32(x: float) -> float:
    """The float32 number nearest x, at or below it: brdfpy holds parameters in float32, and the oracle
    must get the same values (sigma's range ends at pi/2)."""
    y = np.float32(x)
    return float(np.nextafter(y, np.float32(0)) if y > x else y)


#: (model, parameters): sigma from nearly Lambert to the largest roughness, each model's variants; the
#: albedos are float32 numbers.
CASES = [
    ("oren_nayar", {"kd": 0.75, "sigma": _f32(0.05), "variant": "qualitative"}),
    ("oren_nayar", {"kd": 0.75, "sigma": _f32(0.3), "variant": "qualitative"}),
    ("oren_nayar", {"kd": 0.75, "sigma": _f32(HALF_PI), "variant": "compensated"}),
    ("oren_nayar_full", {"kd": 0.75, "sigma": _f32(0.05), "interreflection": True}),
    ("oren_nayar_full", {"kd": 0.75, "sigma": _f32(0.3), "interreflection": True}),
    ("oren_nayar_full", {"kd": 0.875, "sigma": _f32(HALF_PI), "interreflection": True}),
    ("oren_nayar_full", {"kd": 0.75, "sigma": 1.0, "interreflection": False}),
]
FAMILIES = [
    f"{polar}/{azimuth}"
    for polar in ("near_normal", "normal_far", "grazing", "grazing_far", "wide")
    for azimuth in ("same", "opposite", "any")
]
GRID = [(name, params, family) for name, params in CASES for family in FAMILIES]


def _compare(name: str, params: dict, family: str, model=None) -> tuple[np.ndarray, ...]:
    """(error, floor, bound) per sample in units of M, and the angles; ``model`` is brdfpy's by default."""
    rng = np.random.default_rng(sum(f"{name}/{params['sigma']}/{family}".encode()))
    theta_i, theta_r, dphi = _angles(rng, family)
    g64 = _world(rng, theta_i, theta_r, dphi)
    g32 = {k: a.astype(np.float32) for k, a in g64.items()}
    want = om.evaluate(name, params, **g64)[:, 0]
    rounded = om.evaluate(name, params, **{k: a.astype(np.float64) for k, a in g32.items()})[:, 0]
    model = brdfpy.model(name, **params) if model is None else model
    got = model.eval(**g32)[:, 0].astype(np.float64)
    scale = _terms(name, params, theta_i, theta_r, dphi)
    # The derivatives of f in the angles, by central differences of the oracle (float64; the steps stay
    # inside (0, pi/2) for every family).
    h = 1e-7
    d_i, d_r, d_phi = (
        np.abs(_local_oracle(name, params, *up) - _local_oracle(name, params, *down)) / (2 * h)
        for up, down in (
            ((theta_i + h, theta_r, dphi), (theta_i - h, theta_r, dphi)),
            ((theta_i, theta_r + h, dphi), (theta_i, theta_r - h, dphi)),
            ((theta_i, theta_r, dphi + h), (theta_i, theta_r, dphi - h)),
        )
    )
    sensitivity = d_i + d_r + d_phi * (1 / np.sin(theta_i) + 1 / np.sin(theta_r))
    floor = np.abs(rounded - want) / scale
    bound = 4 * floor + ULP * (6 + 4 * sensitivity / scale)
    return np.abs(got - want) / scale, floor, bound, theta_i, theta_r, dphi


@pytest.mark.parametrize(
    ("name", "params", "family"),
    GRID,
    ids=[f"{c[0]}-{c[1]['sigma']:.3g}-{c[2]}" for c in GRID],
)
def test_oren_nayar_stays_at_the_float32_floor_in_adversarial_geometry(
    name: str, params: dict, family: str
) -> None:
    err, floor, bound, theta_i, theta_r, dphi = _compare(name, params, family)
    worst = int(np.argmax(err / bound))
    assert np.all(err <= bound), (
        f"{np.sum(err > bound)} of {err.size} samples off; worst: error {err[worst] / ULP:.3g} ulps of M, "
        f"floor {floor[worst] / ULP:.3g}, bound {bound[worst] / ULP:.3g}; theta_i {theta_i[worst]:.6g}, "
        f"theta_r {theta_r[worst]:.6g}, dphi {dphi[worst]:.6g}"
    )
