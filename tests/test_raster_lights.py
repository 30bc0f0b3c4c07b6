"""brdfpy's lights (``Light.incident``) against the reference lights of ``raster_oracle.lights``:
direction toward the light, irradiance (attenuation, spot cone) and distance at random points."""

from __future__ import annotations

from typing import Any

import brdfpy
import numpy as np
import pytest

from raster_oracle import bridge as rb

CASES: list[rb.Light] = [
    rb.Light("directional", {"direction": (0.3, -1.0, -0.4), "color": (1.0, 0.5, 0.25)}),
    rb.Light("point", {"position": (0.5, 2.0, -1.0), "intensity": 7.0, "attenuation": "inverse_square"}),
    rb.Light("point", {"position": (0.5, 2.0, -1.0), "intensity": (1.0, 2.0, 3.0), "attenuation": "none"}),
    rb.Light("point", {"position": (-1.0, 1.0, 1.0), "intensity": 12.0, "attenuation": (1.0, 0.5, 0.25)}),
    rb.Light(
        "spot",
        {
            "position": (0.0, 3.0, 0.0),
            "direction": (0.2, -1.0, 0.1),
            "intensity": 9.0,
            "inner_angle": 15.0,
            "outer_angle": 40.0,
            "attenuation": "inverse_square",
        },
    ),
    rb.Light(
        "spot",
        {"position": (1, 1, 1), "direction": (-1, -1, -1), "inner_angle": 25.0, "outer_angle": 25.0},
    ),
]


@pytest.mark.parametrize("light", CASES, ids=[f"{c.kind}{i}" for i, c in enumerate(CASES)])
def test_incident_light_matches_reference(light: rb.Light, rng: Any) -> None:
    ours, ref = rb.brdfpy_light(light), rb.oracle_light(light)
    p = rng.uniform(-2, 2, (400, 3)).astype(np.float32).astype(np.float64)
    l_ref, e_ref, d_ref = ref.incident(p)
    inside = 0
    for i, q in enumerate(p):
        got = ours.incident(q)
        if got is None:
            # nothing arrives: outside the cone (the reference's irradiance is 0 there)
            np.testing.assert_allclose(e_ref[i], 0, atol=1e-5 * max(1.0, float(e_ref.max())))
            continue
        inside += 1
        l, e, d = (np.asarray(x, dtype=np.float64) for x in got)
        np.testing.assert_allclose(l, l_ref[i], atol=1e-5)
        # the cone's smoothstep near its edges amplifies float32 rounding of cos(angle) by ~1/(cos i - cos o)
        np.testing.assert_allclose(e, e_ref[i], rtol=2e-4, atol=1e-5 * float(e_ref.max()))
        if np.isfinite(d_ref[i]):
            assert d == pytest.approx(d_ref[i], rel=1e-5)
        else:
            assert not np.isfinite(d)
    assert inside > 40


def test_spot_cone_edges() -> None:
    # on the axis: full intensity; beyond the outer angle: nothing; between: the documented smoothstep
    spot = brdfpy.SpotLight((0, 0, 0), (0, 0, -1), 4.0, inner_angle=20, outer_angle=40, attenuation="none")
    for deg, want in ((0.0, 1.0), (19.9, 1.0), (30.0, None), (40.1, 0.0)):
        a = np.radians(deg)
        p = np.array([np.sin(a), 0.0, -np.cos(a)])
        got = spot.incident(p)
        if want == 0.0:
            assert got is None or np.allclose(got[1], 0)
            continue
        if want is None:
            t = (np.cos(a) - np.cos(np.radians(40))) / (np.cos(np.radians(20)) - np.cos(np.radians(40)))
            want = t * t * (3 - 2 * t)
        assert got is not None
        np.testing.assert_allclose(got[1], 4.0 * want, rtol=1e-4)
