"""``brdfpy.measured``: the tabulated BRDF against an independent NumPy look-up (tests/oracle/measured.py),
its convergence to the model it was sampled from, the MERL file layout, and the parameter fit."""

from __future__ import annotations

import math
import pickle
import struct
from pathlib import Path

import brdfpy
import numpy as np
import pytest
from brdfpy import measured

from conftest import F32_ULP, GIL_RELEASED_FRACTION, log_uniform, python_spins_during, unit
from oracle import measured as om


def _pairs(rng: np.random.Generator, count: int, max_deg: float = 85.0) -> tuple[np.ndarray, np.ndarray]:
    """Unit (l, v) above the +z surface, uniform in solid angle up to ``max_deg``, half near the mirror."""

    def hemi(k: int) -> np.ndarray:
        z = rng.uniform(math.cos(math.radians(max_deg)), 1.0, k)
        phi = rng.uniform(0, 2 * math.pi, k)
        s = np.sqrt(1 - z * z)
        return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1)

    l = hemi(count)
    v = hemi(count)
    near = rng.uniform(size=count) < 0.5
    mirror = l * [-1, -1, 1] + rng.normal(scale=0.1, size=(count, 3))
    mirror[:, 2] = np.abs(mirror[:, 2]) + 0.05
    v = np.where(near[:, None], unit(mirror), v)
    return l, v


CT = {"roughness": 0.3, "kd": [0.5, 0.3, 0.2], "ks": 0.5}


def test_look_up_matches_the_oracle_interpolation() -> None:
    t = measured.Tabulated.from_model(brdfpy.model("cook_torrance", **CT), (16, 12, 24))
    l, v = _pairs(np.random.default_rng(3), 3000, max_deg=89.0)
    got = t.eval(l, v, [0, 0, 1])
    want = om.lookup(t.table, l, v)
    np.testing.assert_allclose(got, want, rtol=2e-4, atol=1e-6)


@pytest.fixture(scope="module")
def sharp_table() -> measured.Tabulated:
    """A sharp Cook-Torrance lobe (roughness 0.05) at MERL resolution: most of the peak lies in the first
    few θ_h cells, where the sqrt index spacing is finest."""
    ct = brdfpy.model("cook_torrance", roughness=0.05, kd=0.0, ks=1.0)
    return measured.Tabulated.from_model(ct, measured.MERL_RESOLUTION)


def _half_diff_directions(theta_h: np.ndarray, theta_d: np.ndarray, phi_d: np.ndarray, phi_h: np.ndarray):
    """Float64 unit (l, v) with n = +z at the given half/difference angles (angles down to 1e-8 rad kept:
    built from sines and cosines of the angles, never from a cosine near 1)."""
    h = np.stack([np.sin(theta_h) * np.cos(phi_h), np.sin(theta_h) * np.sin(phi_h), np.cos(theta_h)], axis=1)
    y = np.stack([-np.sin(phi_h), np.cos(phi_h), np.zeros_like(phi_h)], axis=1)
    x = np.cross(y, h)
    d = np.sin(theta_d)[:, None] * (np.cos(phi_d)[:, None] * x + np.sin(phi_d)[:, None] * y)
    c = np.cos(theta_d)[:, None] * h
    return c + d, c - d


def _wobble(table: np.ndarray, l: np.ndarray, v: np.ndarray, want: np.ndarray, rng: np.random.Generator):
    """How far the oracle look-up moves when l and v turn by 2^-23 rad (four random turns; the largest):
    normalising a float32 direction turns it by about that much."""
    eps = 2 * F32_ULP
    moved = np.zeros_like(want)
    for _ in range(4):
        tl, tv = (unit(np.cross(w, rng.normal(size=w.shape))) for w in (l, v))
        turned = om.lookup(table, l * np.cos(eps) + tl * np.sin(eps), v * np.cos(eps) + tv * np.sin(eps))
        moved = np.maximum(moved, np.abs(turned[:, 1] - want))
    return moved


def _index_sensitivity(table: np.ndarray, th: np.ndarray, td: np.ndarray, pd: np.ndarray) -> np.ndarray:
    """sum over the three index coordinates u of |df/du| (u + 1): what a relative float32 rounding of each
    index coordinate (and its fractional part) costs, by central differences of the oracle interpolant."""
    n_th, n_td, n_pd = table.shape[:3]
    u = (np.sqrt(th / (np.pi / 2)) * n_th, td / (np.pi / 2) * n_td, pd / np.pi * n_pd)

    def at(uh: np.ndarray, ud: np.ndarray, up: np.ndarray) -> np.ndarray:
        angles = ((uh / n_th) ** 2 * np.pi / 2, ud / n_td * np.pi / 2, up / n_pd * np.pi)
        return om.interpolate(table, *angles)[:, 1]

    step = 1e-3
    total = np.zeros_like(th)
    for axis in range(3):
        up, down = list(u), list(u)
        up[axis] = u[axis] + step
        down[axis] = np.maximum(u[axis] - step, 0.0)
        total += np.abs(at(*up) - at(*down)) / (up[axis] - down[axis]) * (u[axis] + 1)
    return total


@pytest.mark.parametrize("family", ["peak", "peak_retro", "peak_tilted"])
def test_look_up_near_the_specular_peak_stays_at_the_float32_floor(
    sharp_table: measured.Tabulated, family: str
) -> None:
    """Near the specular peak (θ_h from 1e-8 to 0.2 rad) and also near the retro direction (θ_d from 1e-7
    to 0.3 rad), with n = +z or in a tilted frame, the look-up of float32 directions matches the float64
    oracle on the exact ones to

        4 floor + 2 wobble + 2^-24 (8 f + 4 S)

    where ``floor`` is the oracle on the float32-rounded directions (one realisation of input rounding),
    ``wobble`` how far the oracle moves when l and v turn by 2^-23 rad (what float32 normalisation does), f
    the value (the interpolation's own roundings) and S = sum |df/du| (u + 1) over the index coordinates
    (their float32 rounding). Measured: at most 0.63 of that (largest relative error 8.1e-6, floor 6.8e-6).
    Angles by acos of a float32 cosine (the former form) are off by up to 4e-4 rad near 0, 1.5 θ_h cells
    at the peak: the library was up to 3.2e-4 (relative) off the oracle there, where the floor is 9.5e-6,
    and a float32 emulation of those angles exceeds this bound in 65-76 % of the samples, by up to 500
    times."""
    table = sharp_table.table
    rng = np.random.default_rng(sum(family.encode()))
    count = 20000
    theta_h = log_uniform(rng, 1e-8, 0.2, count)
    theta_d = log_uniform(rng, 1e-7, 0.3, count) if family == "peak_retro" else rng.uniform(0, 1.4, count)
    phi_d, phi_h = rng.uniform(0, np.pi, count), rng.uniform(0, 2 * np.pi, count)
    l, v = _half_diff_directions(theta_h, theta_d, phi_d, phi_h)
    keep = (l[:, 2] > 0) & (v[:, 2] > 0)
    l, v, theta_h, theta_d = l[keep], v[keep], theta_h[keep], theta_d[keep]
    n = np.array([0.0, 0.0, 1.0])
    if family == "peak_tilted":
        # A random rotation: brdfpy gets the turned directions and normal rounded to float32; the floor
        # turns the rounded ones back with a float64 frame around the rounded normal.
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        rot = q * np.sign(np.linalg.det(q))
        l32, v32, n32 = ((w @ rot.T).astype(np.float32) for w in (l, v, n))
        nz = unit(n32.astype(np.float64))
        tx = unit(rot[:, 0] - (rot[:, 0] @ nz) * nz)
        frame = np.stack([tx, np.cross(nz, tx), nz])
        l_back, v_back = (w.astype(np.float64) @ frame.T for w in (l32, v32))
    else:
        l32, v32, n32 = l.astype(np.float32), v.astype(np.float32), n.astype(np.float32)
        l_back, v_back = l32.astype(np.float64), v32.astype(np.float64)
    want = om.lookup(table, l, v)[:, 1]
    floor = np.abs(om.lookup(table, l_back, v_back)[:, 1] - want)
    got = sharp_table.eval(l32, v32, n32)[:, 1].astype(np.float64)
    pd = om.half_diff(l, v)[2]
    sensitivity = _index_sensitivity(table, theta_h, theta_d, pd)
    bound = 4 * floor + 2 * _wobble(table, l, v, want, rng) + F32_ULP * (8 * want + 4 * sensitivity)
    err = np.abs(got - want)
    worst = int(np.argmax(err / bound))
    assert np.all(err <= bound), (
        f"{np.sum(err > bound)} of {err.size} samples off; "
        f"worst: relative error {err[worst] / want[worst]:.3g}, "
        f"floor {floor[worst] / want[worst]:.3g}, bound {bound[worst] / want[worst]:.3g}; "
        f"theta_h {theta_h[worst]:.3g}, theta_d {theta_d[worst]:.3g}"
    )


def test_table_nodes_hold_the_model_values() -> None:
    m = brdfpy.model("cook_torrance", **CT)
    t = measured.Tabulated.from_model(m, (8, 8, 16))
    tab = t.table
    assert tab.shape == (8, 8, 16, 3) and tab.dtype == np.float32
    # Node (i, j, k) = (3, 2, 5): θ_h = (3/8)²·π/2, θ_d = 2/8·π/2, φ_d = 5/16·π, directions built here.
    th, td, pd = (3 / 8) ** 2 * math.pi / 2, 2 / 8 * math.pi / 2, 5 / 16 * math.pi
    h = np.array([math.sin(th), 0, math.cos(th)])
    x = np.array([math.cos(th), 0, -math.sin(th)])
    y = np.array([0.0, 1.0, 0.0])
    d = np.array([math.sin(td) * math.cos(pd), math.sin(td) * math.sin(pd), math.cos(td)])
    l = d[0] * x + d[1] * y + d[2] * h
    v = -d[0] * x - d[1] * y + d[2] * h
    np.testing.assert_allclose(tab[3, 2, 5], m.eval(l, v, [0, 0, 1]), rtol=1e-5)


def test_interpolation_error_falls_as_the_square_of_the_spacing() -> None:
    m = brdfpy.model("cook_torrance", **CT)
    l, v = _pairs(np.random.default_rng(4), 4000, max_deg=70.0)
    exact = m.eval(l, v, [0, 0, 1]).astype(np.float64)
    errs = []
    for res in (8, 16, 32):
        got = measured.Tabulated.from_model(m, (res, res, 2 * res)).eval(l, v, [0, 0, 1])
        errs.append(float(np.sqrt(np.sum((got - exact) ** 2) / np.sum(exact**2))))
    # Trilinear interpolation is second order: each halving of the spacing divides the error by ~4.
    # Measured with half the views near the mirror direction: 0.20, 0.038, 0.0094 (ratios 5.3, 4.1).
    assert errs[0] / errs[1] > 3.3 and errs[1] / errs[2] > 3.3, errs
    assert errs[2] < 0.015, errs


def test_lambertian_table_is_exact_and_zero_below_the_horizon() -> None:
    t = measured.Tabulated.from_model(brdfpy.model("lambert", kd=0.6), (4, 4, 4))
    got = t.eval([0.2, 0.1, 1.0], [-0.5, 0.3, 1.0], [0, 0, 1])
    assert got.shape == (3,)
    np.testing.assert_allclose(got, 0.6 / math.pi, rtol=1e-6)
    below = t.eval([[0.2, 0.1, -1.0], [0, 0, 1]], [[0, 0, 1], [0.3, 0, -0.1]], [0, 0, 1])
    np.testing.assert_array_equal(below, 0.0)


def test_table_is_reciprocal() -> None:
    t = measured.Tabulated.from_model(brdfpy.model("cook_torrance", **CT), (16, 16, 32))
    l, v = _pairs(np.random.default_rng(5), 2000)
    np.testing.assert_allclose(t.eval(l, v, [0, 0, 1]), t.eval(v, l, [0, 0, 1]), rtol=1e-4, atol=1e-7)


def test_look_up_does_not_depend_on_the_frame() -> None:
    # An isotropic table: rotating l, v and n together (any rotation, including about n) changes nothing.
    t = measured.Tabulated.from_model(brdfpy.model("cook_torrance", **CT), (16, 16, 32))
    rng = np.random.default_rng(10)
    l, v = _pairs(rng, 2000)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    rot = q * np.sign(np.linalg.det(q))  # a proper rotation
    n = np.array([0.0, 0.0, 1.0])
    np.testing.assert_allclose(t.eval(l @ rot.T, v @ rot.T, n @ rot.T), t.eval(l, v, n), rtol=2e-4, atol=1e-6)


def test_merl_file_round_trips_with_the_documented_layout(tmp_path: Path) -> None:
    t = measured.Tabulated.from_model(brdfpy.model("cook_torrance", **CT), (6, 5, 8))
    path = tmp_path / "ct.binary"
    t.save_merl(path)
    raw = path.read_bytes()
    assert struct.unpack("<3i", raw[:12]) == (6, 5, 8)
    data = np.frombuffer(raw[12:], dtype="<f8").reshape(3, 6, 5, 8)
    scale = np.array([1.0, 1.15, 1.66]) / 1500.0
    np.testing.assert_allclose(np.moveaxis(data, 0, -1) * scale, t.table, rtol=1e-7)
    back = measured.Tabulated.load_merl(path)
    assert back.shape == (6, 5, 8)
    np.testing.assert_allclose(back.table, t.table, rtol=1e-7)


def test_bad_tables_and_files_are_refused_with_the_reason() -> None:
    with pytest.raises(ValueError, match="table"):
        measured.Tabulated(np.zeros((4, 4, 3)))
    with pytest.raises(ValueError, match="finite"):
        measured.Tabulated(np.full((2, 2, 2, 3), np.nan))
    with pytest.raises(ValueError, match=">= 0"):
        measured.Tabulated(-np.ones((2, 2, 2, 3)))
    with pytest.raises(ValueError, match="n_theta_h"):
        measured.Tabulated(np.ones((1, 2, 2, 3)))
    with pytest.raises(ValueError, match="bytes"):
        measured.Tabulated.from_merl_bytes(struct.pack("<3i", 90, 90, 180) + b"\0" * 100)
    with pytest.raises(ValueError, match="anisotropic"):
        measured.Tabulated.from_model(brdfpy.model("ward"), (4, 4, 4))
    t = measured.Tabulated(np.ones((2, 2, 2, 3)))
    with pytest.raises(ValueError, match="l:"):
        t.eval(np.ones((4, 2)), [0, 0, 1], [0, 0, 1])
    with pytest.raises(ValueError, match="v"):
        t.eval([0, 0, 1], [[np.nan, 0, 1]], [0, 0, 1])
    with pytest.raises(TypeError, match="model"):
        measured.Tabulated.from_model("lambert", (4, 4, 4))  # type: ignore[arg-type]


def _samples(model: brdfpy.Model, count: int, noise: float, seed: int) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    l, v = _pairs(rng, count, max_deg=80.0)
    f = model.eval(l, v, [0, 0, 1]) * np.exp(noise * rng.normal(size=(count, 3)))
    return l, v, f


def test_fit_recovers_cook_torrance_parameters_from_another_start() -> None:
    truth = brdfpy.model("cook_torrance", roughness=0.18, kd=[0.4, 0.25, 0.1], ks=0.8)
    l, v, f = _samples(truth, 2000, 0.0, 6)
    res = measured.fit("cook_torrance", l, v, [0, 0, 1], f, start={"roughness": 0.5, "kd": 0.5, "ks": 0.3})
    assert res["converged"] and res["samples_used"] == 2000
    assert res["values"]["roughness"] == pytest.approx(0.18, abs=1e-3)
    assert res["values"]["kd"] == pytest.approx((0.4, 0.25, 0.1), abs=1e-3)
    assert res["values"]["ks"] == pytest.approx((0.8, 0.8, 0.8), abs=1e-3)
    np.testing.assert_allclose(res["model"].eval(l, v, [0, 0, 1]), f, rtol=1e-3, atol=1e-6)


def test_fit_with_noise_keeps_a_bounded_error() -> None:
    truth = brdfpy.model("blinn_phong", shininess=60.0, kd=0.25, ks=0.5)
    l, v, f = _samples(truth, 2000, 0.05, 7)
    res = measured.fit("blinn_phong", l, v, [0, 0, 1], f, start={"shininess": 5.0, "kd": 0.9})
    # 5 % log-normal noise: the residual is the noise, the parameters move by well under 2 %.
    assert res["rms_log_error"] == pytest.approx(0.05, abs=0.005)
    assert res["values"]["shininess"] == pytest.approx(60.0, rel=0.02)
    assert res["values"]["kd"] == pytest.approx((0.25,) * 3, rel=0.02)


def test_fit_refuses_bad_requests_naming_the_argument() -> None:
    l, v, f = _samples(brdfpy.model("lambert"), 10, 0.0, 8)
    with pytest.raises(ValueError, match="kdd"):
        measured.fit("lambert", l, v, [0, 0, 1], f, start={"kdd": 0.5})
    with pytest.raises(ValueError, match="values"):
        measured.fit("lambert", l, v, [0, 0, 1], np.full_like(f, np.nan), start={"kd": 0.5})
    with pytest.raises(ValueError, match="scalar and color"):
        measured.fit("cook_torrance", l, v, [0, 0, 1], f, start={"masking": "smith"})
    with pytest.raises(ValueError, match="both fixed and free"):
        measured.fit("lambert", l, v, [0, 0, 1], f, start={"kd": 0.5}, fixed={"kd": 0.5})
    with pytest.raises(ValueError, match="values"):
        measured.fit("lambert", l, v, [0, 0, 1], f[:3], start={"kd": 0.5})


def test_python_threads_run_during_a_fit(one_thread: None) -> None:
    truth = brdfpy.model("cook_torrance", roughness=0.3)
    l, v, f = _samples(truth, 60_000, 0.0, 9)
    start = {"roughness": 0.9, "ks": 0.2, "kd": 0.3}
    speed, result = python_spins_during(
        lambda: measured.fit("cook_torrance", l, v, [0, 0, 1], f, start=start)
    )
    # A fit of ~0.4 s: with the GIL held the loop would stand still while it runs.
    assert speed > GIL_RELEASED_FRACTION, speed
    # This many samples take the parallel residual path; it must find the same answer.
    assert result["values"]["roughness"] == pytest.approx(0.3, abs=1e-4)


def test_a_measured_table_is_a_model_that_evaluates_as_the_table_and_pickles() -> None:
    ct = brdfpy.model("cook_torrance", roughness=0.3, kd=0.2)
    table = measured.Tabulated.from_model(ct, (24, 24, 48))
    m = table.as_model()
    assert (m.name, m.params, m.physical, m.anisotropic) == ("measured", {}, True, False)
    assert "Tabulated(shape=(24, 24, 48))" in repr(m)
    rng = np.random.default_rng(3)
    l, v = _pairs(rng, 5000)
    assert np.array_equal(m.eval(l, v, [0, 0, 1]), table.eval(l, v, [0, 0, 1]))
    # shade = f_r · max(n·l, 0), as for every physical model
    f, cos_l = m.eval(l, v, [0, 0, 1]), np.maximum(l[:, 2:3], 0.0)
    np.testing.assert_allclose(m.shade(l, v, [0, 0, 1]), f * cos_l, rtol=1e-6, atol=1e-12)
    again = pickle.loads(pickle.dumps(m))
    assert np.array_equal(again.eval(l, v, [0, 0, 1]), m.eval(l, v, [0, 0, 1]))
    # The half/difference table is reciprocal by construction.
    assert brdfpy.checks.reciprocity_error(m) < 1e-4
    with pytest.raises(ValueError, match="built from a table"):
        brdfpy.model("measured")
    with pytest.raises(ValueError, match="_table"):
        brdfpy.Model("lambert", _table=table._inner)


def test_a_measured_material_renders_like_the_model_it_was_measured_from() -> None:
    # Seed 003, "Rendering from Measured BRDF": look-up with interpolation during rendering. The image of
    # the table converges to the image of the analytic model at the interpolation's second order.
    ct = brdfpy.model("cook_torrance", roughness=0.3, kd=0.2, metal="au")
    cam = brdfpy.Camera.perspective((0, 0, 3), (0, 0, 0), (0, 1, 0), 45)

    def render(material: brdfpy.Model) -> brdfpy.Image:
        scene = brdfpy.Scene(ambient_light=0.0)
        scene.add(brdfpy.icosphere(5), material)
        scene.add_light(brdfpy.DirectionalLight((-1, -1, -1), 3.0))
        scene.add_light(brdfpy.PointLight((2, 2, 2), 10.0, attenuation="inverse_square"))
        return scene.render(cam, 160, 120, outputs="all")

    want = render(ct)
    inside = want.triangle_id >= 0
    errors = []
    for res in [(45, 45, 90), (90, 90, 180)]:
        got = render(measured.Tabulated.from_model(ct, res).as_model())
        assert np.array_equal(got.triangle_id, want.triangle_id)
        errors.append(np.abs(got.hdr - want.hdr)[inside].sum() / np.abs(want.hdr)[inside].sum())
    # measured here: 1.6e-3 and 3.9e-4
    assert errors[1] < 1e-3, errors
    assert errors[0] / errors[1] > 3.0, errors
