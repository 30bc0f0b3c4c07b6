"""brdfpy.views: every view's data against the independent oracle (tests/oracle/views.py for the directions,
tests/oracle/models.py for the values) and against physics; spherical angles; bad input."""

from __future__ import annotations

import math
from typing import Any

import brdfpy
import numpy as np
import pytest
from brdfpy import views
from brdfpy.measured import Tabulated

from conftest import REGISTRY_MODELS, assert_close, model_defaults, well_conditioned
from oracle import models as om
from oracle import views as ov

ANISOTROPIC = {"ward", "ashikhmin_shirley"}


def _oracle(name: str, l: np.ndarray, v: np.ndarray) -> np.ndarray:
    """f_r of the registry defaults of ``name`` at float32-rounded directions (n = +z, tangent +x)."""
    l32 = np.broadcast_to(np.asarray(l, np.float32), np.shape(v)).astype(np.float64)
    v32 = np.asarray(v, np.float32).astype(np.float64)
    n = np.broadcast_to([0.0, 0.0, 1.0], v32.shape)
    t = np.broadcast_to([1.0, 0.0, 0.0], v32.shape)
    return om.evaluate(name, model_defaults(name), l32, v32, n, t)


def _compared(name: str, l: np.ndarray, v: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Rows where the oracle is well conditioned (drops toon band edges and cusps, as test_models does)."""
    geo = {
        "l": np.broadcast_to(np.asarray(l, np.float32), np.shape(v)).copy(),
        "v": np.asarray(v, np.float32),
        "n": np.broadcast_to(np.float32([0, 0, 1]), np.shape(v)).copy(),
        "tangent": np.broadcast_to(np.float32([1, 0, 0]), np.shape(v)).copy(),
    }
    ref = _oracle(name, l, v)
    return well_conditioned(lambda **g: om.evaluate(name, model_defaults(name), **g), geo, rng, ref)


# --- spherical angles --------------------------------------------------------------------------------------


def test_from_spherical_and_back_in_both_units() -> None:
    theta = np.array([[0.0, 30.0, 90.0], [45.0, 120.0, 180.0]])
    phi = np.array([0.0, -45.0, 170.0])
    w = brdfpy.vectors.from_spherical(theta, phi, degrees=True)
    assert w.shape == (2, 3, 3) and w.dtype == np.float32
    np.testing.assert_allclose(w, ov.spherical(np.radians(theta), np.radians(phi)), atol=1e-7)
    t, p = brdfpy.vectors.to_spherical(w, degrees=True)
    np.testing.assert_allclose(t, theta, atol=2e-5)
    # The azimuth is arbitrary at the poles; elsewhere it comes back.
    off_pole = (theta % 180) != 0
    np.testing.assert_allclose(p[off_pole], np.broadcast_to(phi, theta.shape)[off_pole], atol=2e-5)
    wr = brdfpy.vectors.from_spherical(np.radians(theta), np.radians(phi), degrees=False)
    np.testing.assert_array_equal(w, wr)
    tr, _ = brdfpy.vectors.to_spherical(w, degrees=False)
    np.testing.assert_allclose(tr, np.radians(theta), atol=4e-7)


def test_to_spherical_is_accurate_near_the_pole_and_zero_for_a_zero_vector() -> None:
    # acos(cos θ) of a float32 cosine would be off by ~3e-4 rad near 0; atan2 keeps 1e-7 rad angles.
    t, _ = brdfpy.vectors.to_spherical([1e-7, 0.0, 1.0], degrees=False)
    assert t == pytest.approx(1e-7, rel=1e-6)
    t, p = brdfpy.vectors.to_spherical([0.0, 0.0, 0.0], degrees=True)
    assert (t, p) == (0.0, 0.0)


def test_spherical_angles_need_explicit_units_and_finite_values() -> None:
    with pytest.raises(TypeError, match="degrees"):
        brdfpy.vectors.from_spherical(1.0, 0.0)  # type: ignore[call-arg]
    with pytest.raises(TypeError, match="degrees"):
        brdfpy.vectors.from_spherical(1.0, 0.0, degrees="yes")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="theta"):
        brdfpy.vectors.from_spherical(np.nan, 0.0, degrees=True)
    with pytest.raises(ValueError, match="do not broadcast"):
        brdfpy.vectors.from_spherical([1, 2], [1, 2, 3], degrees=True)
    with pytest.raises(ValueError, match=r"\(\.\.\., 3\)"):
        brdfpy.vectors.to_spherical([1.0, 2.0], degrees=True)


# --- polar slice -------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", REGISTRY_MODELS)
@pytest.mark.parametrize("cosine", [False, True])
def test_polar_slice_matches_the_oracle(name: str, cosine: bool, rng: np.random.Generator) -> None:
    theta_i, phi = 35.0, 20.0
    p = views.polar(name, theta_i, phi=phi, n=361, cosine=cosine)
    assert p.values.shape == (361, 3) and p.values.dtype == np.float32
    np.testing.assert_allclose(p.theta_o, np.linspace(-90, 90, 361), atol=1e-12)
    l, v = ov.in_plane(math.radians(theta_i), math.radians(phi), np.radians(p.theta_o))
    want = _oracle(name, l, v)
    if cosine:
        want = want * np.maximum(v[:, 2:3].astype(np.float32), 0)
    assert_close(p.values, want, _compared(name, l, v, rng), what=f"{name} polar")


@pytest.mark.parametrize(
    "name", ["lambert", "oren_nayar", "phong", "blinn_phong", "cook_torrance", "lafortune"]
)
def test_at_normal_incidence_an_isotropic_polar_slice_is_mirror_symmetric(name: str) -> None:
    p = views.polar(name, 0.0, n=181)
    np.testing.assert_allclose(p.values, p.values[::-1], rtol=1e-5, atol=1e-7 * p.values.max())


def test_a_phong_lobe_is_symmetric_about_the_mirror_direction() -> None:
    # f = ks (n+2)/(2π) cos^n(r, v) depends on the angle to the mirror direction only: in the plane of
    # incidence f(θ_i + δ) = f(θ_i − δ) while both stay above the horizon.
    m = brdfpy.model("phong", kd=0.0)
    p = views.polar(m, 30.0, n=721)  # 0.25° steps: θ_o = 30 + δ at index 480 + k
    k = np.arange(1, 200)
    np.testing.assert_allclose(p.values[480 + k], p.values[480 - k], rtol=2e-4)
    assert p.theta_o[int(p.luminance.argmax())] == pytest.approx(30.0)


# --- lobe -------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", REGISTRY_MODELS)
def test_lobe_vertices_are_the_oracle_radius_along_the_grid(name: str, rng: np.random.Generator) -> None:
    lobe = views.lobe(name, 40.0, phi=30.0, n_theta=16, n_phi=32, radius="f_cos", channel="luminance")
    dirs = ov.lobe_directions(16, 32)
    np.testing.assert_allclose(lobe.directions, dirs, atol=1e-7)
    l = ov.spherical(np.radians(40.0), np.radians(30.0))
    want = _oracle(name, l, dirs) * np.maximum(dirs[:, 2:3].astype(np.float32), 0)
    assert_close(lobe.values, want, _compared(name, l, dirs, rng), what=f"{name} lobe")
    lum = lobe.values.astype(np.float64) @ np.array(views.LUMINANCE)
    np.testing.assert_allclose(lobe.radii, lum, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(
        lobe.mesh.vertices, lobe.directions * lobe.radii[:, None], rtol=1e-6, atol=1e-9
    )
    assert lobe.mesh.n_faces == 32 * (2 * 16 - 1)
    np.testing.assert_allclose(lobe.light, l, atol=1e-7)


def test_a_ggx_lobe_peaks_at_the_mirror_direction() -> None:
    m = brdfpy.model("cook_torrance", distribution="ggx", roughness=0.05, kd=0.0)
    lobe = views.lobe(m, 50.0, phi=60.0, n_theta=180, n_phi=360, radius="f")
    peak = lobe.directions[int(lobe.radii.argmax())]
    mirror = ov.spherical(np.radians(50.0), np.radians(60.0 + 180.0))
    assert math.degrees(math.acos(min(1.0, float(peak @ mirror)))) < 1.0


def test_the_lobe_renders_through_the_rasterizer() -> None:
    lobe = views.lobe("cook_torrance", 45.0)
    scene = brdfpy.Scene()
    scene.add(lobe.mesh, brdfpy.model("lambert"))
    scene.add_light(brdfpy.DirectionalLight((-1, -1, -2)))
    centre, radius = lobe.mesh.bounding_sphere()
    cam = brdfpy.Camera.framing(centre, radius, direction=(1, -2, 1), up=(0, 0, 1))
    img = scene.render(cam, 64, 64, cull_back_faces=False)
    assert img.covered_pixels > 100


# --- θh/θd slice ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", REGISTRY_MODELS)
def test_half_diff_slice_matches_the_oracle_at_rotated_difference_vectors(
    name: str, rng: np.random.Generator
) -> None:
    s = views.half_diff_slice(name, phi_d=70.0, size=(24, 20))
    assert s.values.shape == (20, 24, 3) and s.valid.shape == (20, 24)
    np.testing.assert_allclose(np.radians(s.theta_h), ov.cell_centres(24), atol=1e-12)
    np.testing.assert_allclose(np.radians(s.theta_d), ov.cell_centres(20), atol=1e-12)
    th, td = np.meshgrid(ov.cell_centres(24), ov.cell_centres(20))
    l, v = ov.half_diff_directions(th.reshape(-1), td.reshape(-1), math.radians(70.0))
    np.testing.assert_array_equal(s.valid.reshape(-1), (l[:, 2] > 0) & (v[:, 2] > 0))
    geo_l = l.astype(np.float32).astype(np.float64)
    want = om.evaluate(
        name,
        model_defaults(name),
        geo_l,
        v.astype(np.float32).astype(np.float64),
        np.broadcast_to([0.0, 0.0, 1.0], l.shape),
        np.broadcast_to([1.0, 0.0, 0.0], l.shape),
    )
    geo = {
        "l": l.astype(np.float32),
        "v": v.astype(np.float32),
        "n": np.broadcast_to(np.float32([0, 0, 1]), l.shape).copy(),
        "tangent": np.broadcast_to(np.float32([1, 0, 0]), l.shape).copy(),
    }
    mask = well_conditioned(lambda **g: om.evaluate(name, model_defaults(name), **g), geo, rng, want)
    assert_close(s.values.reshape(-1, 3), want, mask, what=f"{name} slice")


def test_the_slice_shares_its_angles_with_the_measured_look_up() -> None:
    # A table sampled from a model and the model itself give the same slice up to interpolation: both go
    # through the same (θh, θd, φd) code, so the slice of the table is the table at its own coordinates.
    m = brdfpy.model("cook_torrance", roughness=0.4, kd=(0.5, 0.3, 0.2))
    t = Tabulated.from_model(m, (45, 45, 90))
    a, b = views.half_diff_slice([m, t], size=32, phi_d=90.0)
    ok = a.valid & (a.luminance > 0)
    rel = np.abs(b.luminance[ok] - a.luminance[ok]) / a.luminance[ok]
    assert np.median(rel) < 2e-3 and b.model.name == "measured"


# --- albedo -----------------------------------------------------------------------------------------------


def test_white_lambert_albedo_is_one_at_every_incidence() -> None:
    a = views.albedo(brdfpy.model("lambert", kd=1.0), np.linspace(0, 90, 19))
    np.testing.assert_allclose(a.values, 1.0, atol=2e-6)


@pytest.mark.parametrize("name", ["lambert", "oren_nayar", "oren_nayar_full", "phong", "ward", "lafortune"])
def test_albedo_curve_matches_a_dense_oracle_quadrature(name: str) -> None:
    theta = np.array([0.0, 25.0, 50.0, 75.0])
    a = views.albedo(name, theta)
    for k, t in enumerate(np.radians(theta)):
        l = ov.spherical(np.array(t), np.array(0.0))
        want = ov.albedo(lambda v, l=l: _oracle(name, l, v) * v[:, 2:3])
        np.testing.assert_allclose(a.values[k], want, rtol=2e-3, err_msg=f"{name} at {theta[k]}°")


def test_albedo_table_varies_one_parameter() -> None:
    tab = views.albedo_table("cook_torrance", "roughness", [0.1, 0.5, 1.0], [0.0, 60.0])
    assert tab.values.shape == (3, 2, 3)
    for p, r in enumerate([0.1, 0.5, 1.0]):
        np.testing.assert_array_equal(
            tab.values[p], views.albedo(brdfpy.model("cook_torrance", roughness=r), [0.0, 60.0]).values
        )
    default = views.albedo_table("oren_nayar", "sigma")
    lo, hi = (
        brdfpy.model_info("oren_nayar")["params"][
            [p["name"] for p in brdfpy.model_info("oren_nayar")["params"]].index("sigma")
        ][k]
        for k in ("min", "max")
    )
    assert default.param_values[0] == pytest.approx(lo + (hi - lo) / 8) and default.param_values[-1] == hi
    with pytest.raises(ValueError, match="no parameter"):
        views.albedo_table("lambert", "roughness")
    with pytest.raises(ValueError, match="not a scalar"):
        views.albedo_table("cook_torrance", "distribution")


# --- lit sphere -------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", REGISTRY_MODELS)
def test_lit_sphere_is_the_oracle_shading_of_the_analytic_sphere(name: str, rng: np.random.Generator) -> None:
    size = 48
    img = views.lit_sphere(name, theta_i=40.0, phi=30.0, size=size, ambient=0.0, tonemap="clamp")
    mask, n = ov.sphere_normals(size)
    np.testing.assert_array_equal(img.mask, mask)
    l = ov.spherical(np.radians(40.0), np.radians(30.0))
    nn = n[mask].astype(np.float32)
    t = np.cross([0.0, 1.0, 0.0], nn)  # circles around the vertical axis
    physical = brdfpy.model(name).physical
    geo = {
        "l": np.broadcast_to(l.astype(np.float32), nn.shape).copy(),
        "v": np.broadcast_to(np.float32([0, 0, 1]), nn.shape).copy(),
        "n": nn,
        "tangent": t.astype(np.float32),
    }

    def oracle(**g: np.ndarray) -> np.ndarray:
        return om.evaluate(name, model_defaults(name), quantity="shade", **g) * (math.pi if physical else 1)

    want = oracle(**{k: a.astype(np.float64) for k, a in geo.items()})
    assert_close(img.hdr[mask], want, well_conditioned(oracle, geo, rng, want), what=f"{name} sphere")
    assert np.all(img.hdr[~mask] == 0)


def test_the_sky_adds_ambient_times_the_albedo() -> None:
    m = brdfpy.model("lambert", kd=(0.6, 0.4, 0.2))
    lit = views.lit_sphere(m, size=32, ambient=0.0)
    sky = views.lit_sphere(m, size=32, ambient=0.25)
    added = sky.hdr[sky.mask] - lit.hdr[lit.mask]
    np.testing.assert_allclose(
        added, np.broadcast_to(0.25 * np.array([0.6, 0.4, 0.2]), added.shape), atol=1e-6
    )


def test_auto_tone_map_puts_the_peak_at_white_without_clipping_a_disc() -> None:
    m = brdfpy.model("blinn_phong", shininess=200.0)
    img = views.lit_sphere(m, size=128)
    peak = img.hdr[img.mask].max()
    assert peak > 5  # a normalised highlight: far above 1
    lum = img.rgb[img.mask].max(axis=1)
    # Clamping would saturate every pixel above 1; the auto white point saturates only the peak.
    assert (img.hdr[img.mask].max(axis=1) > 1).sum() > 20 and (lum == 255).sum() <= 4
    clamped = views.lit_sphere(m, size=128, tonemap="clamp")
    assert (clamped.rgb[clamped.mask].max(axis=1) == 255).sum() > 20


def test_several_models_give_several_results() -> None:
    names = ["lambert", "ward"]
    assert [p.model.name for p in views.polar(names)] == names
    assert len(views.lit_sphere(names, size=16)) == 2
    assert len(views.albedo(names, [10.0])) == 2
    assert isinstance(views.lobe("phong"), views.Lobe)


# --- bad input --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("call", "exc", "match"),
    [
        (lambda: views.polar("nope"), ValueError, "unknown model"),
        (lambda: views.polar([]), ValueError, "models: is empty"),
        (lambda: views.polar("lambert", 95.0), ValueError, r"theta_i.*\[0°, 90°\].*95"),
        (lambda: views.polar("lambert", -1.0), ValueError, "theta_i"),
        (lambda: views.polar("lambert", float("nan")), ValueError, "theta_i"),
        (lambda: views.polar("lambert", n=1), ValueError, r"^n: must be in"),
        (lambda: views.polar(3.0), TypeError, "models"),  # type: ignore[call-overload]
        (lambda: views.lobe("lambert", radius="area"), ValueError, "radius"),  # type: ignore[call-overload]
        (lambda: views.lobe("lambert", channel="alpha"), ValueError, "channel"),  # type: ignore[call-overload]
        (lambda: views.half_diff_slice("lambert", phi_d=200.0), ValueError, "phi_d"),
        (lambda: views.half_diff_slice("lambert", size=0), ValueError, "n_theta_h"),
        (lambda: views.albedo("lambert", [10.0, 100.0]), ValueError, "theta_i"),
        (lambda: views.albedo("lambert", []), ValueError, "empty"),
        (lambda: views.lit_sphere("lambert", size=2), ValueError, "size"),
        (lambda: views.lit_sphere("lambert", tonemap="gamma"), ValueError, "tonemap"),
        (lambda: views.lit_sphere("lambert", light=(0, 0, 0)), ValueError, "light"),
        (lambda: views.lit_sphere("lambert", light=(0, 0, 1), theta_i=10.0), ValueError, "not both"),
        (lambda: brdfpy.model("cook_torrance", roughness=float("inf")), ValueError, "roughness"),
    ],
)
def test_bad_input_is_refused_with_the_argument_named(call: Any, exc: type, match: str) -> None:
    with pytest.raises(exc, match=match):
        call()
