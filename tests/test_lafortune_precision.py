"""Lafortune's lobes stay at float32's floor where the lobe base ``s = Cx lx vx + Cy ly vy + Cz lz vz`` is
hardest to get right: directions near the normal, near the mirror direction (also at grazing), near the
retro direction, with exponents up to 500 (a relative error ``e`` of ``s`` becomes ``n e`` in ``s^n``).

The reference is the float64 oracle on the exact (float64) directions; brdfpy gets them rounded to float32.
Two things bound what float32 can do:

* the rounding of the inputs: the oracle on the float32-rounded directions moves by ``floor`` (one
  realisation per sample; it reaches 1 where rounding moves a grazing direction across the horizon);
* float32 arithmetic on unit vectors: normalising l, v and n and summing the products moves ``s`` by a
  few ulps (2^-24) of the size of its gradient, ``|M l| + |M v|`` with ``M = diag(Cx, Cy, Cz)`` (about 2 at
  a Phong peak; only ``|l_perp| + |v_perp|`` for a lobe with Cz = 0 near the normal, where
  ``s ~ |l_perp||v_perp|``), and ``s^n`` multiplies the relative error by ``n``.

So each sample must match to ``4 floor + 5 n 2^-24 (|M l| + |M v|)/s`` (relative). Measured: at most 0.80
of that (Phong n = 500 at grazing mirror directions; the anisotropic frame path 0.73). The former
isotropic form ``Cx (l·v - (n·l)(n·v)) + Cz (n·l)(n·v)`` fails it: a float32 emulation of it reaches 1.6
times the bound at a Phong peak near the normal and 7 600 times for a lobe with Cz = 0 there (the library
measured 116 times the true value, floor 0.19), where ``l·v`` and ``(n·l)(n·v)`` are both ~1 and their
difference ~|l_perp||v_perp| keeps only their rounding.
"""

from __future__ import annotations

import brdfpy
import numpy as np
import pytest

from conftest import F32_ULP, direction, in_random_frame, log_uniform, unit
from oracle import models as om

ULP = F32_ULP
COUNT = 20000


def _adversarial(rng: np.random.Generator, family: str) -> dict[str, np.ndarray]:
    """Float64 l, v (both above the surface), n and tangent, built in a local frame and turned to a
    random world frame."""
    phi = rng.uniform(0, 2 * np.pi, COUNT)
    if family == "near_normal":  # both within 1e-5 .. 0.05 rad of the normal
        l = direction(np.cos(log_uniform(rng, 1e-5, 0.05, COUNT)), phi)
        v = direction(np.cos(log_uniform(rng, 1e-5, 0.05, COUNT)), rng.uniform(0, 2 * np.pi, COUNT))
    else:  # v within 1e-6 .. 0.1 rad of the mirror (or retro) direction of l
        grazing = family.endswith("grazing")
        cos_l = log_uniform(rng, 1e-4, 0.1, COUNT) if grazing else rng.uniform(1e-3, 1, COUNT)
        l = direction(cos_l, phi)
        target = l * [-1.0, -1.0, 1.0] if family.startswith("mirror") else l
        axis = unit(np.cross(target, rng.normal(size=target.shape)))
        turn = log_uniform(rng, 1e-6, 0.1, COUNT)[:, None]
        v = target * np.cos(turn) + axis * np.sin(turn)
    return in_random_frame(rng, l, v)


#: (name, one lobe [cx, cy, cz, n], the families where it is non-zero): Phong's lobe at a large exponent, a
#: lobe with no normal term (its base is the tangent-plane dot product alone), an off-specular one, a
#: retro-reflector, an anisotropic one.
LOBES = [
    ("phong-500", [-1.0, -1.0, 1.0, 500.0], ["near_normal", "mirror", "mirror_grazing", "retro"]),
    ("phong-50", [-1.0, -1.0, 1.0, 50.0], ["near_normal", "mirror", "mirror_grazing", "retro"]),
    ("tangent-only-3", [-1.0, -1.0, 0.0, 3.0], ["near_normal", "mirror", "mirror_grazing"]),
    ("tangent-only-1", [-1.0, -1.0, 0.0, 1.0], ["near_normal", "mirror", "mirror_grazing"]),
    ("off-specular-200", [-1.0, -1.0, 0.6, 200.0], ["mirror", "mirror_grazing"]),
    ("retro-200", [1.0, 1.0, 1.0, 200.0], ["near_normal", "mirror", "retro", "retro_grazing"]),
    ("anisotropic-500", [-1.1, -0.9, 1.0, 500.0], ["near_normal", "mirror", "mirror_grazing", "retro"]),
]
CASES = [(name, row, family) for name, row, families in LOBES for family in families]


@pytest.mark.parametrize(("name", "row", "family"), CASES, ids=[f"{c[0]}-{c[2]}" for c in CASES])
def test_lobes_stay_at_the_float32_floor_in_adversarial_geometry(
    name: str, row: list[float], family: str
) -> None:
    rng = np.random.default_rng(sum(f"{name}/{family}".encode()))
    g64 = _adversarial(rng, family)
    g32 = {k: a.astype(np.float32) for k, a in g64.items()}
    params = {"kd": 0.0, "ks": 1.0, "lobes": [row], "power": "exact"}
    want = om.evaluate("lafortune", params, **g64)[:, 0]
    rounded = om.evaluate("lafortune", params, **{k: a.astype(np.float64) for k, a in g32.items()})[:, 0]
    got = brdfpy.model("lafortune", kd=0.0, ks=1.0, lobes=[row]).eval(**g32)[:, 0].astype(np.float64)
    # Samples that matter: within 1e-6 of the family's largest value, and far from float32's underflow.
    compared = (want > 1e-6 * want.max()) & (want > 1e-30)
    assert compared.sum() >= 100, f"only {compared.sum()} samples inside the lobe"
    # How far the base s = l^T M v moves when l and v move by one float32 ulp: |M l| + |M v|, relative
    # to s (large at a lobe's edge, and near the normal for a lobe with Cz = 0, where s ~ |l_perp||v_perp|).
    geo = om.geometry(g64["l"], g64["v"], g64["n"], g64["tangent"])
    c = np.asarray(row[:3])
    ml = np.linalg.norm(np.stack(geo.loc(geo.l), axis=-1) * c, axis=-1)
    mv = np.linalg.norm(np.stack(geo.loc(geo.v), axis=-1) * c, axis=-1)
    sensitivity = (ml + mv)[compared] / want[compared] ** (1.0 / row[3])
    want, rounded, got = want[compared], rounded[compared], got[compared]
    floor = np.abs(rounded - want) / want
    bound = 4 * floor + 5 * row[3] * ULP * sensitivity
    err = np.abs(got - want) / want
    worst = int(np.argmax(err / bound))
    assert np.all(err <= bound), (
        f"{np.sum(err > bound)} of {err.size} samples off; worst: relative error {err[worst]:.3g}, "
        f"floor {floor[worst]:.3g}, bound {bound[worst]:.3g}"
    )
