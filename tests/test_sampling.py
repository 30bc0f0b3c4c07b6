"""Importance sampling as a specification: every sampler draws what its pdf says (Pearson's chi-square
over a grid of models, parameters and view angles, graded down to very low roughness and grazing views), the
pdf is the published density (the NumPy oracle), the weight is ``shade/pdf`` bit for bit, the pdf
integrates to the fraction of samples that do not fail, sampling reproduces the quadrature albedo, results
do not depend on threads or batching, and bad input names the argument.
"""

from __future__ import annotations

import math
from typing import Any

import brdfpy
import numpy as np
import pytest
from brdfpy import checks

from conftest import GIL_RELEASED_FRACTION, python_spins_during
from oracle import sampling as osamp

N = (0.0, 0.0, 1.0)
T = (1.0, 0.0, 0.0)


def view(theta_deg: float, phi_deg: float = 0.0) -> np.ndarray:
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)], dtype=np.float32)


# (label, model name, parameters, zoom of the chi-square grid). Very low roughness and large exponents get a
# grid graded toward the lobe (zoom > 1) so that the lobe spans many cells.
CASES: list[tuple[str, str, dict[str, Any], float]] = [
    ("lambert", "lambert", {}, 1.0),
    ("lambert_classic", "lambert_classic", {}, 1.0),
    ("oren_nayar", "oren_nayar", {"sigma": 1.2}, 1.0),
    ("oren_nayar_full", "oren_nayar_full", {}, 1.0),
    ("toon", "toon", {}, 1.0),
    ("phong_classic", "phong_classic", {"shininess": 50.0}, 2.0),
    ("blinn_phong_classic", "blinn_phong_classic", {"shininess": 80.0}, 2.0),
    ("phong n=1", "phong", {"shininess": 1.0}, 1.0),
    ("phong n=1000 specular", "phong", {"shininess": 1000.0, "kd": 0.0}, 4.0),
    ("blinn_phong exact n=10", "blinn_phong", {"shininess": 10.0, "normalization": "exact"}, 1.0),
    ("blinn_phong n=5000", "blinn_phong", {"shininess": 5000.0, "kd": 0.1}, 4.0),
    ("ggx 0.5", "cook_torrance", {"roughness": 0.5}, 1.0),
    ("ggx 0.1 conductor", "cook_torrance", {"roughness": 0.1, "fresnel": "conductor", "metal": "au"}, 2.0),
    ("ggx 0.01", "cook_torrance", {"roughness": 0.01, "kd": 0.0}, 4.0),
    ("ggx 0.002", "cook_torrance", {"roughness": 0.002, "kd": 0.0}, 6.0),
    ("beckmann 0.3", "cook_torrance", {"distribution": "beckmann", "roughness": 0.3}, 1.0),
    ("beckmann 0.02", "cook_torrance", {"distribution": "beckmann", "roughness": 0.02, "kd": 0.0}, 4.0),
    ("gaussian 0.2", "cook_torrance", {"distribution": "gaussian", "roughness": 0.2}, 2.0),
    ("blinn_phong D 0.3", "cook_torrance", {"distribution": "blinn_phong", "roughness": 0.3}, 1.0),
    ("two GGX lobes", "cook_torrance", {"roughness": 0.05, "roughness2": 0.6, "weight2": 0.3}, 3.0),
    ("strauss", "strauss", {"smoothness": 0.7}, 2.0),
    ("ward isotropic", "ward", {"alpha_x": 0.2, "alpha_y": 0.2}, 1.0),
    ("ward anisotropic", "ward", {"alpha_x": 0.04, "alpha_y": 0.4, "kd": 0.0}, 3.0),
    ("ward 1992", "ward", {"normalization": "ward"}, 1.0),
    ("ashikhmin_shirley", "ashikhmin_shirley", {}, 2.0),
    ("ashikhmin_shirley 10000", "ashikhmin_shirley", {"nu": 10000.0, "nv": 10000.0, "kd": 0.0}, 4.0),
    ("lafortune", "lafortune", {}, 2.0),
    (
        "lafortune three lobes",
        "lafortune",
        {"lobes": [[-1.0, -1.0, 1.0, 30.0], [-0.3, -0.9, 0.7, 4.0], [0.6, 0.6, 0.6, 2.0]]},
        2.0,
    ),
]
ANGLES = [0.0, 30.0, 60.0, 80.0, 89.0]


def build(name: str, params: dict[str, Any]) -> brdfpy.Model:
    return brdfpy.model(name, **params)


def measured_model() -> brdfpy.Model:
    ct = brdfpy.model("cook_torrance", roughness=0.2, kd=0.3)
    return brdfpy.measured.Tabulated.from_model(ct, resolution=(32, 32, 64)).as_model()


def test_every_sampler_passes_chi_square_over_models_parameters_and_view_angles() -> None:
    """28 parameter sets + a measured table, five view angles each (0 to 89 deg), 300 000 samples per test.
    Sidak-corrected at 1 % for the whole grid: a correct suite fails with probability 1 %."""
    runs = [(label, build(name, params), zoom) for label, name, params, zoom in CASES]
    runs.append(("measured", measured_model(), 2.0))
    tests = len(runs) * len(ANGLES)
    p_values = []
    for label, m, zoom in runs:
        for a in ANGLES:
            r = checks.chi2(
                m,
                view(a, 25.0),
                N,
                tangent=T,
                samples=300_000,
                n_theta=48,
                n_phi=96,
                zoom=zoom,
                ires=5,
                test_count=tests,
            )
            assert r["passed"], (
                f"{label} at {a} deg: p = {r['p_value']:.3g}, "
                f"chi2 {r['statistic']:.1f} / {r['dof']}, {r['problems']}"
            )
            assert r["dof"] > 50, f"{label} at {a} deg: only {r['dof']} degrees of freedom"
            p_values.append(r["p_value"])
    # Correct samplers give uniform p-values: their median is near 1/2 and none is tiny.
    assert 0.25 < float(np.median(p_values)) < 0.75, sorted(p_values)[:10]


@pytest.mark.parametrize(
    ("drawn", "claimed"),
    [
        ({"roughness": 0.3}, {"roughness": 0.33}),  # GGX 10 % off in roughness
        ({"roughness": 0.01}, {"roughness": 0.011}),  # ... and at very low roughness
        ({"distribution": "beckmann", "roughness": 0.2}, {"distribution": "ggx", "roughness": 0.2}),
    ],
)
def test_a_sampler_that_draws_another_density_fails_chi_square(
    drawn: dict[str, Any], claimed: dict[str, Any]
) -> None:
    truth = brdfpy.model("cook_torrance", kd=0.0, **claimed)
    wrong = brdfpy.model("cook_torrance", kd=0.0, **drawn)
    for a in [0.0, 60.0]:
        r = checks.chi2(truth, view(a), N, sample=wrong.sample, zoom=4.0, samples=1_000_000)
        assert not r["passed"] and r["p_value"] < 1e-6, (drawn, a, r["p_value"])
        # ... while the right sampler passes the same test.
        assert checks.chi2(truth, view(a), N, zoom=4.0, samples=1_000_000)["passed"]


def test_a_density_that_misses_part_of_the_lobe_fails_chi_square() -> None:
    """A pdf that claims no mass in one quadrant of azimuths (where samples do land) fails outright."""
    m = brdfpy.model("lambert")

    def partial(l: np.ndarray, v: Any, n: Any, tangent: Any = None) -> np.ndarray:
        p = m.pdf(l, v, n, tangent)
        return np.where((l[:, 0] > 0) & (l[:, 1] > 0), 0.0, p * 4 / 3).astype(np.float32)

    r = checks.chi2(m, view(20.0), N, pdf=partial, samples=100_000)
    assert not r["passed"] and r["problems"], r


def _local(l: np.ndarray) -> np.ndarray:
    return l.astype(np.float64)


@pytest.mark.parametrize(
    ("name", "params", "density"),
    [
        ("lambert", {}, lambda l, v: osamp.cosine(l)),
        ("oren_nayar", {}, lambda l, v: osamp.cosine(l)),
        ("phong", {"kd": 0.0, "shininess": 40.0}, lambda l, v: osamp.lobe(l, v, 40.0)),
        ("blinn_phong", {"kd": 0.0, "shininess": 60.0}, lambda l, v: osamp.half_power(l, v, 60.0)),
        (
            "cook_torrance",
            {"kd": 0.0, "roughness": 0.2},
            lambda l, v: osamp.visible_normals(l, v, "ggx", 0.2),
        ),
        (
            "cook_torrance",
            {"kd": 0.0, "distribution": "beckmann", "roughness": 0.25},
            lambda l, v: osamp.visible_normals(l, v, "beckmann", 0.25),
        ),
        (
            "cook_torrance",
            {"kd": 0.0, "distribution": "blinn_phong", "roughness": 0.3},
            lambda l, v: osamp.half_power(l, v, 2 / 0.3**2 - 2 + 1),
        ),
        ("ward", {"kd": 0.0, "alpha_x": 0.1, "alpha_y": 0.3}, lambda l, v: osamp.ward(l, v, 0.1, 0.3)),
        (
            "ashikhmin_shirley",
            {"kd": 0.0, "nu": 200.0, "nv": 20.0},
            lambda l, v: osamp.ashikhmin_shirley(l, v, 200.0, 20.0),
        ),
        (
            "lafortune",
            {"kd": 0.0, "lobes": [[-0.7, -0.9, 0.8, 12.0]]},
            lambda l, v: osamp.lobe(l, v, 12.0, (-0.7, -0.9, 0.8)),
        ),
    ],
)
def test_the_pdf_is_the_published_density_of_each_technique(
    name: str, params: dict[str, Any], density: Any, rng: np.random.Generator
) -> None:
    m = brdfpy.model(name, **params)
    k = 4000
    z = rng.uniform(0.02, 1.0, (k, 2))
    phi = rng.uniform(0, 2 * np.pi, (k, 2))
    s = np.sqrt(1 - z**2)
    dirs = np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=-1)
    l, v = dirs[:, 0], dirs[:, 1]
    # Half of the pairs near the lobe: l drawn by the sampler itself.
    ls, _, _ = m.sample(v[: k // 2], N, tangent=T, seed=3)
    l[: k // 2] = ls
    got = m.pdf(l.astype(np.float32), v.astype(np.float32), N, T).astype(np.float64)
    want = density(_local(l.astype(np.float32)), _local(v.astype(np.float32)))
    ok = l[:, 2] > 0
    np.testing.assert_allclose(got[ok], want[ok], rtol=2e-4, atol=1e-6 * np.max(want))


def test_mixtures_weigh_their_lobes_by_estimated_albedo() -> None:
    """Cook-Torrance with a diffuse term: ``p = (mean(kd) p_cos + mean(ks F(n.v)) p_ggx) / sum``
    (Schlick's F)."""
    kd, ks, f0, alpha = np.array([0.5, 0.3, 0.1]), 0.8, 0.04, 0.3
    m = brdfpy.model("cook_torrance", kd=kd.tolist(), ks=ks, f0=f0, roughness=alpha)
    v = view(50.0)
    l = np.stack([view(t, p) for t in np.linspace(1, 85, 12) for p in np.linspace(0, 350, 12)])
    fresnel = f0 + (1 - f0) * (1 - v[2]) ** 5
    w = [kd.mean(), ks * fresnel]
    lv = np.broadcast_to(v, l.shape).astype(np.float64)
    want = osamp.mixture(
        w, [osamp.cosine(l.astype(np.float64)), osamp.visible_normals(l.astype(np.float64), lv, "ggx", alpha)]
    )
    np.testing.assert_allclose(m.pdf(l, v, N), want, rtol=2e-4)


ALL = [(label, name, params) for label, name, params, _ in CASES]


@pytest.mark.parametrize(("label", "name", "params"), ALL, ids=[c[0] for c in ALL])
def test_weight_is_shade_over_pdf_bit_for_bit_and_never_nan(
    label: str, name: str, params: dict[str, Any]
) -> None:
    m = build(name, params)
    v = np.stack([view(a, 40.0 * a) for a in np.linspace(0, 89.5, 64)])
    l, w, p = m.sample(v, N, tangent=T, seed=9)
    assert np.all(np.isfinite(l)) and np.all(np.isfinite(w)) and np.all(np.isfinite(p))
    assert np.all(w >= 0) and np.all(p >= 0)
    ok = p > 0
    assert ok.mean() > 0.5, label
    np.testing.assert_array_equal(m.pdf(l, v, N, T), p)
    want = m.shade(l[ok], v[ok], N, T) / p[ok, None]
    np.testing.assert_array_equal(w[ok], want)
    np.testing.assert_array_equal(w[~ok], 0.0)
    np.testing.assert_allclose(np.linalg.norm(l[ok], axis=1), 1.0, atol=1e-6)


@pytest.mark.parametrize(("label", "name", "params"), ALL, ids=[c[0] for c in ALL])
def test_the_pdf_integrates_to_the_fraction_of_samples_that_do_not_fail(
    label: str, name: str, params: dict[str, Any]
) -> None:
    m = build(name, params)
    cos = np.array([1.0, 0.7, 0.3, 0.05])
    integral = checks.pdf_integral(m, cos)
    by_sampling = checks.albedo_by_sampling(m, cos, samples=200_000)
    frac = by_sampling["valid_fraction"]
    se = np.sqrt(frac * (1 - frac) / 200_000)
    # The graded quadrature resolves smooth lobes to < 1e-4; the binomial fraction has error se.
    assert np.all(np.abs(integral - frac) <= 4 * se + 2e-4), (integral, frac)
    assert np.all(integral <= 1 + 1e-4)
    if name in ("lambert", "lambert_classic", "oren_nayar", "oren_nayar_full", "toon"):
        np.testing.assert_allclose(integral, 1.0, atol=1e-6)  # cosine-weighted: never fails


@pytest.mark.parametrize(("label", "name", "params"), ALL, ids=[c[0] for c in ALL])
def test_albedo_by_sampling_matches_the_quadrature_albedo(
    label: str, name: str, params: dict[str, Any]
) -> None:
    m = build(name, params)
    cos = np.array([1.0, 0.6, 0.2])
    r = checks.albedo_by_sampling(m, cos, samples=1 << 17, seed=4)
    # Monte Carlo error (4 standard errors) plus the quadrature's and float32's share (1e-4 relative).
    quad = checks.directional_albedo(m, cos).astype(np.float64)
    rel = 1e-4
    if name == "toon":
        # The toon bands are step functions: the graded rule converges slowly across their edges
        # (measured at cos 1: 4.286, 4.189, 4.228 with 8, 32, 64 points per panel; 2^22 samples: 4.222).
        quad = checks.directional_albedo(m, cos, 64, 64, min_panel=1e-7).astype(np.float64)
        rel = 2e-3
    bound = 4 * r["std_error"] + rel * np.maximum(quad, 1e-3) + 1e-6
    assert np.all(np.abs(r["albedo"] - quad) <= bound), (r["albedo"], quad, r["std_error"])


def test_lambert_and_the_course_lambert_are_sampled_with_zero_variance() -> None:
    r = checks.albedo_by_sampling(brdfpy.model("lambert", kd=(0.2, 0.5, 0.9)), [1.0, 0.3], samples=1000)
    np.testing.assert_allclose(r["albedo"], [[0.2, 0.5, 0.9]] * 2, rtol=1e-6)
    assert np.all(r["std_error"] < 1e-6)


def test_a_measured_table_samples_its_albedo_and_its_pdf_integrates_to_one() -> None:
    m = measured_model()
    cos = np.array([0.9, 0.4])
    r = checks.albedo_by_sampling(m, cos, samples=1 << 17)
    quad = checks.directional_albedo(m, cos).astype(np.float64)
    assert np.all(np.abs(r["albedo"] - quad) <= 4 * r["std_error"] + 2e-3 * quad), (r["albedo"], quad)
    # Piecewise constant over half-vector cells: the quadrature is first-order across the jumps.
    np.testing.assert_allclose(checks.pdf_integral(m, cos), r["valid_fraction"], atol=1e-2)


def test_samples_do_not_depend_on_the_thread_count_or_the_batch_shape(restore_threads: None) -> None:
    m = brdfpy.model("cook_torrance", distribution="beckmann", roughness=0.2)
    count = 50_000  # several chunks, GIL released
    v = view(40.0)
    runs = []
    for threads in (1, 2, 4):
        brdfpy.set_num_threads(threads)
        runs.append(m.sample(v, N, seed=123, count=count))
    for r in runs[1:]:
        for a, b in zip(runs[0], r):
            np.testing.assert_array_equal(a, b)
    # The same numbers given explicitly, broadcast views given as rows, and one sample at a time.
    u = brdfpy.sampling.uniform(count, seed=123)
    explicit = m.sample(np.tile(v, (count, 1)), N, u)
    for a, b in zip(runs[0], explicit):
        np.testing.assert_array_equal(a, b)
    for i in [0, 1, 777, count - 1]:
        one = m.sample(v, N, u[i])
        np.testing.assert_array_equal(one[0], runs[0][0][i])
        np.testing.assert_array_equal(one[1], runs[0][1][i])
        assert one[2].shape == () and one[2] == runs[0][2][i]
    other = m.sample(v, N, seed=124, count=count)
    assert not np.array_equal(other[0], runs[0][0])


def test_uniform_numbers_are_the_documented_splitmix64_stream() -> None:
    def mix(z: int) -> int:
        m64 = (1 << 64) - 1
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & m64
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & m64
        return z ^ (z >> 31)

    seed, gamma = 77, 0x9E3779B97F4A7C15
    key = mix(seed)
    want = [
        [(mix((key + (3 * i + d + 1) * gamma) & ((1 << 64) - 1)) >> 40) / 2**24 for d in range(3)]
        for i in range(5)
    ]
    np.testing.assert_array_equal(brdfpy.sampling.uniform(5, seed), np.array(want, dtype=np.float32))


def test_sampling_releases_the_gil(one_thread: None) -> None:
    m = brdfpy.model("cook_torrance")
    spins, (l, _, _) = python_spins_during(lambda: m.sample(view(30.0), N, count=3_000_000))
    assert l.shape == (3_000_000, 3)
    assert spins > GIL_RELEASED_FRACTION, spins


def test_views_below_the_surface_give_zero_samples_not_nan() -> None:
    m = brdfpy.model("cook_torrance")
    l, w, p = m.sample([[0.3, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]], N)
    np.testing.assert_array_equal(l, 0.0)
    np.testing.assert_array_equal(w, 0.0)
    np.testing.assert_array_equal(p, 0.0)
    assert m.pdf([0, 0, 1], [0.3, 0.0, -1.0], N) == 0.0
    assert m.pdf([0.3, 0.0, -1.0], [0, 0, 1], N) == 0.0


@pytest.mark.parametrize(
    ("kwargs", "exc", "words"),
    [
        ({"u": [0.2, 1.0, 0.5]}, brdfpy.BrdfError, ["u", "[0, 1)", "1.0"]),
        ({"u": [[0.2, 0.5, 0.5], [0.1, -0.1, 0.3]]}, brdfpy.BrdfError, ["u", "u[1]"]),
        ({"u": [0.2, float("nan"), 0.5]}, brdfpy.BrdfError, ["u"]),
        ({"u": [0.2, 0.5]}, ValueError, ["u", "shape"]),
        ({"u": np.zeros((5, 3)), "count": 3}, ValueError, ["count", "5"]),
        ({"seed": -1}, ValueError, ["seed"]),
        ({"seed": 1.5}, TypeError, ["seed"]),
        ({"count": 0}, ValueError, ["count"]),
        ({"v": [0.0, float("inf"), 1.0]}, brdfpy.BrdfError, ["v", "non-finite"]),
        ({"v": np.ones((4, 3)), "n": np.ones((3, 3))}, ValueError, ["n", "broadcast"]),
        ({"tangent": [1.0, 0.0]}, ValueError, ["tangent", "shape"]),
    ],
)
def test_bad_input_names_the_argument(kwargs: dict[str, Any], exc: type[Exception], words: list[str]) -> None:
    m = brdfpy.model("phong")
    args: dict[str, Any] = {"v": [0.0, 0.3, 1.0], "n": N}
    args.update(kwargs)
    v, n = args.pop("v"), args.pop("n")
    with pytest.raises(exc) as e:
        m.sample(v, n, **args)
    for w in words:
        assert w in str(e.value), str(e.value)


def test_bad_input_to_pdf_and_the_checks_names_the_argument() -> None:
    m = brdfpy.model("phong")
    with pytest.raises(brdfpy.BrdfError, match="l"):
        m.pdf([[0, 0, 1], [0, float("nan"), 1]], [0, 0, 1], N)
    with pytest.raises(ValueError, match="cos_theta_v"):
        checks.pdf_integral(m, [0.0])
    with pytest.raises(ValueError, match="cos_theta_v"):
        checks.albedo_by_sampling(m, [1.5])
    with pytest.raises(ValueError, match="zoom"):
        checks.chi2(m, view(10.0), zoom=0.5)
    with pytest.raises(ValueError, match="v"):
        checks.chi2(m, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="significance"):
        checks.chi2(m, view(10.0), significance=0.0)
