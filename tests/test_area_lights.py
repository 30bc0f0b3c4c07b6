"""Area lights (brdfpy.SphereLight, brdfpy.RectLight): a surface emitting a constant radiance L, estimated by
Monte Carlo with multiple importance sampling between the light and the material, with traced visibility
(soft shadows).

The reference values are analytic: a white Lambert floor (ρ = 1) reflects ``L_o = ρ/π · E`` with

- a sphere of radius r whose centre is at distance d, fully above the horizon: ``E = π L sin²α cos θ``,
  ``sin α = r/d`` — the irradiance of a point light of intensity ``I = L π r²`` at the centre;
- a rectangle: Lambert's polygon formula ``E = L/2 Σ_i γ_i n·û_i`` (Baum, Rushmeier & Winget 1989; Arvo 1995).

Monte Carlo error: every test measures the scatter σ of the per-pixel estimates about the analytic value
and allows the mean over k pixels to differ from it by at most 4σ/√k (a 4-standard-error bound: it fails
for a biased estimator, here by construction an error of a few % would fail), plus 1e-4 relative for
float32 rounding.
"""

from __future__ import annotations

import math
import pickle

import brdfpy
import numpy as np
import pytest

SIZE = 64
HEIGHT = 1.0  # the orthographic view spans [-0.5, 0.5]² of the floor


def floor_camera(height: float = HEIGHT, eye_y: float = 0.5) -> brdfpy.Camera:
    # Looking straight down (screen right = +x, screen down = +z); between the floor and any blocker
    # above y = eye_y, which the near plane clips (the shadow rays still see it).
    return brdfpy.Camera.orthographic((0, eye_y, 0), (0, 0, 0), up=(0, 0, -1), height=height, near=0.05)


def floor_points(size: int = SIZE, height: float = HEIGHT) -> np.ndarray:
    """World positions (size, size, 3) of the pixel centres on the floor y = 0 (row → z, column → x)."""
    c = ((np.arange(size) + 0.5) / size - 0.5) * height
    x, z = np.meshgrid(c, c)
    return np.stack([x, np.zeros_like(x), z], axis=-1)


def floor_scene(*lights: brdfpy.Light, blocker: bool = False) -> brdfpy.Scene:
    scene = brdfpy.Scene()
    scene.add(brdfpy.plane(4.0, 4), brdfpy.model("lambert", kd=1.0))
    if blocker:
        # An opaque sheet at y = 1 over x < 0 (facing down, so that the light below sees its back too).
        sheet = np.array([[1, 0, 0, -1.5], [0, -1, 0, 1.0], [0, 0, 1, 0], [0, 0, 0, 1]], float)
        scene.add(brdfpy.plane(3.0, 2), "lambert", sheet)
    for light in lights:
        scene.add_light(light)
    return scene


def render_floor(scene: brdfpy.Scene, size: int = SIZE, height: float = HEIGHT, **kw: object) -> np.ndarray:
    img = scene.render(floor_camera(height), size, size, outputs=("hdr",), **kw)  # type: ignore[arg-type]
    return img.hdr[..., 1].astype(np.float64)


def within_mc_error(estimate: np.ndarray, truth: np.ndarray) -> tuple[float, float]:
    """(relative error of the mean, its allowed bound 4σ/√k + 1e-4) over the pixels."""
    rel = estimate / truth - 1.0
    err = abs(rel.mean())
    bound = 4.0 * rel.std() / math.sqrt(rel.size) + 1e-4
    return err, bound


def lambert_polygon_irradiance(p: np.ndarray, corners: np.ndarray, n: np.ndarray) -> np.ndarray:
    """E/L = ½ Σ_i γ_i n·û_i at points p (..., 3) for a convex polygon (corners (k, 3)) fully above the
    horizon of normal n, with the corners' order oriented so that E > 0."""
    r = corners[None, None, :, :] - p[..., None, :]
    r /= np.linalg.norm(r, axis=-1, keepdims=True)
    total = np.zeros(p.shape[:-1])
    k = len(corners)
    for i in range(k):
        a, b = r[..., i, :], r[..., (i + 1) % k, :]
        gamma = np.arccos(np.clip(np.sum(a * b, axis=-1), -1.0, 1.0))
        u = np.cross(a, b)
        u /= np.linalg.norm(u, axis=-1, keepdims=True)
        total += gamma * (u @ n)
    return 0.5 * np.abs(total)


# -- against the analytic irradiance ----------------------------------------------------------------------


def test_a_sphere_light_gives_pi_l_sin2_alpha_on_a_white_lambert_floor() -> None:
    center, r, radiance = np.array([0.1, 1.5, -0.05]), 0.4, 8.0
    img = render_floor(floor_scene(brdfpy.SphereLight(center, r, radiance)), area_samples=16)
    p = floor_points()
    to = center - p
    d = np.linalg.norm(to, axis=-1)
    cos_theta = to[..., 1] / d
    assert (d * cos_theta > r).all()  # fully above every pixel's horizon
    e = math.pi * radiance * (r / d) ** 2 * cos_theta
    err, bound = within_mc_error(img, e / math.pi)
    assert err < bound, (err, bound)
    # Each pixel alone is close too (16 MIS iterations of a light filling a 15° cone: a few % at most).
    assert np.abs(img / (e / math.pi) - 1).max() < 0.1


def test_a_small_distant_sphere_light_is_the_equivalent_point_light() -> None:
    center, r, radiance = (0.7, 4.0, -0.4), 0.05, 2000.0
    sphere = render_floor(floor_scene(brdfpy.SphereLight(center, r, radiance)), area_samples=4)
    point = render_floor(floor_scene(brdfpy.PointLight(center, intensity=radiance * math.pi * r**2)))
    err, bound = within_mc_error(sphere, point)
    assert err < bound, (err, bound)
    assert np.abs(sphere / point - 1).max() < 1e-2


@pytest.mark.parametrize("two_sided", [False, True])
def test_a_rectangle_light_overhead_matches_lamberts_polygon_formula(two_sided: bool) -> None:
    center, e0, e1, radiance = np.array([0.05, 0.8, 0.0]), np.array([0.6, 0, 0]), np.array([0, 0, 0.9]), 5.0
    light = brdfpy.RectLight(center, e0, e1, radiance, two_sided=two_sided)
    assert light.normal == (0.0, -1.0, 0.0) and light.area == pytest.approx(0.54)
    img = render_floor(floor_scene(light), area_samples=32)
    corners = np.array(
        [center + sa * e0 / 2 + sb * e1 / 2 for sa, sb in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    )
    e = radiance * lambert_polygon_irradiance(floor_points(), corners, np.array([0.0, 1.0, 0.0]))
    err, bound = within_mc_error(img, e / math.pi)
    assert err < bound, (err, bound)
    # The light's own vector irradiance (Light.incident) is the same formula.
    l, irr, _ = light.incident((0.0, 0.0, 0.0))
    assert irr[1] * l[1] == pytest.approx(
        radiance * lambert_polygon_irradiance(np.zeros((1, 1, 3)), corners, np.array([0.0, 1.0, 0.0]))[0, 0],
        rel=1e-4,
    )


def test_a_one_sided_rectangle_lights_nothing_behind_it() -> None:
    up = brdfpy.RectLight((0, 0.8, 0), (0, 0, 0.6), (0.6, 0, 0), 5.0)  # z × x = +y: faces away from the floor
    assert up.normal == (0.0, 1.0, 0.0)
    assert up.incident((0, 0, 0)) is None
    assert np.all(render_floor(floor_scene(up), 16, area_samples=4) == 0.0)


def test_the_estimate_converges_as_one_over_root_samples() -> None:
    light = brdfpy.RectLight((0, 0.5, 0), (1.5, 0, 0), (0, 0, 1.5), 3.0)
    corners = np.array([(-0.75, 0.5, -0.75), (0.75, 0.5, -0.75), (0.75, 0.5, 0.75), (-0.75, 0.5, 0.75)])
    truth = 3.0 * lambert_polygon_irradiance(floor_points(32), corners, np.array([0.0, 1.0, 0.0])) / math.pi
    rmse = [
        float(np.sqrt(np.mean((render_floor(floor_scene(light), 32, area_samples=n) / truth - 1) ** 2)))
        for n in (4, 64)
    ]
    # 16× the samples: 4× less noise (within 30 %).
    assert 0.7 * 4 < rmse[0] / rmse[1] < 1.3 * 4, rmse


# -- soft shadows ---------------------------------------------------------------------------------------


def penumbra_width(radius: float) -> float:
    """10 %–90 % width of the shadow edge on the floor cast by a sheet at y = 1 over x < 0 under a sphere
    light of ``radius`` at (0, 2, 0): the shadowed floor over the unshadowed one, averaged along z."""
    light = brdfpy.SphereLight((0, 2, 0), radius, 10.0)
    size, height = 160, 2.0
    lit = render_floor(floor_scene(light), size, height, area_samples=64)
    shadowed = render_floor(floor_scene(light, blocker=True), size, height, area_samples=64)
    profile = (shadowed / lit)[size // 4 : 3 * size // 4].mean(axis=0)
    x = ((np.arange(size) + 0.5) / size - 0.5) * height
    assert profile[0] < 0.02 and profile[-1] > 0.98, profile  # umbra on the left, full light on the right
    assert np.all(np.diff(profile) > -0.05), profile  # monotone up to noise
    return float(np.interp(0.9, profile, x) - np.interp(0.1, profile, x))


def test_the_penumbra_widens_with_the_light_radius() -> None:
    # Through the sheet's edge (x = 0, y = 1) from the light's rim (x = ±r, y = 2) to the floor (y = 0): the
    # penumbra spans x ∈ [−r, r]; a disc's 10 %–90 % occlusion lies between ±0.63 r (the segment of a disc
    # cut at 0.63 r holds 10 % of its area), width ≈ 1.25 r.
    small, large = penumbra_width(0.15), penumbra_width(0.45)
    assert small == pytest.approx(1.25 * 0.15, rel=0.25), small
    assert large == pytest.approx(1.25 * 0.45, rel=0.25), large
    assert large / small == pytest.approx(3.0, rel=0.2), (small, large)


def test_a_point_light_casts_a_hard_shadow_with_the_same_scene() -> None:
    size, height = 160, 2.0
    point = brdfpy.PointLight((0, 2, 0), 10.0)
    lit = render_floor(floor_scene(point), size, height, shadows=True)
    shadowed = render_floor(floor_scene(point, blocker=True), size, height, shadows=True)
    profile = (shadowed / lit)[size // 2]
    assert set(np.round(profile, 6)) == {0.0, 1.0}


# -- determinism, input, pickling -------------------------------------------------------------------------


def busy_scene() -> brdfpy.Scene:
    scene = brdfpy.Scene(ambient_light=0.05, environment=brdfpy.Environment.sky(intensity=0.3))
    scene.add(brdfpy.plane(4.0, 6), "lambert")
    scene.add(
        brdfpy.icosphere(3),
        brdfpy.model("cook_torrance", roughness=0.3),
        brdfpy.transforms.translate((0, 0.5, 0)) @ brdfpy.transforms.scale(0.5),
    )
    scene.add_light(brdfpy.SphereLight((1, 2, 1), 0.3, 20.0, color=(1, 0.9, 0.8)))
    scene.add_light(brdfpy.RectLight((-1, 1.5, 0), (0, 0, 1), (0.5, -0.5, 0), 4.0, two_sided=True))
    scene.add_light(brdfpy.PointLight((0, 3, 2), 5.0))
    return scene


@pytest.mark.parametrize(
    "options",
    [{"shading": "phong", "samples": 4}, {"shading": "gouraud", "env_mode": "monte_carlo", "env_samples": 4}],
)
def test_renders_are_bit_identical_at_any_thread_count(
    options: dict[str, object], restore_threads: None
) -> None:
    scene = busy_scene()
    cam = brdfpy.Camera.perspective((0.5, 2.0, 4.0), (0, 0.3, 0), fovy=45)
    out = []
    for n in (1, 2, 4):
        brdfpy.set_num_threads(n)
        img = scene.render(
            cam, 48, 36, outputs=("hdr",), area_samples=4, area_seed=3, shadows=True, **options
        )  # type: ignore[arg-type]
        out.append(img.hdr)
    assert np.isfinite(out[0]).all() and out[0].max() > 0
    assert np.array_equal(out[0], out[1]) and np.array_equal(out[0], out[2])
    other = scene.render(cam, 48, 36, outputs=("hdr",), area_samples=4, area_seed=4, shadows=True, **options)  # type: ignore[arg-type]
    assert not np.array_equal(out[0], other.hdr)


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: brdfpy.SphereLight((0, 1, 0), 0.0), "radius"),
        (lambda: brdfpy.SphereLight((0, 1, 0), -1.0), "radius"),
        (lambda: brdfpy.SphereLight((0, 1, 0), math.inf), "radius"),
        (lambda: brdfpy.SphereLight((0, 1, 0), math.nan), "radius"),
        (lambda: brdfpy.SphereLight((0, math.nan, 0), 1.0), "center"),
        (lambda: brdfpy.SphereLight((0, 1, 0), 1.0, -2.0), "intensity"),
        (lambda: brdfpy.SphereLight((0, 1, 0), 1.0, color=math.inf), "color"),
        (lambda: brdfpy.RectLight((0, 1, 0), (0, 0, 0), (0, 0, 1)), "edge0"),
        (lambda: brdfpy.RectLight((0, 1, 0), (1, 0, 0), (math.inf, 0, 1)), "edge1"),
        (lambda: brdfpy.RectLight((0, 1, 0), (1, 0, 0), (-2, 0, 0)), "edge0, edge1"),
        (lambda: brdfpy.RectLight((0, 1, 0), (1e-30, 0, 0), (0, 0, 1)), "edge0"),  # |edge0| underflows
        (lambda: brdfpy.RectLight((0, 1, 0), (1e-15, 0, 0), (0, 0, 1e-15)), "edge0, edge1"),  # the area does
        (lambda: brdfpy.RectLight((math.inf, 1, 0), (1, 0, 0), (0, 0, 1)), "center"),
    ],
)
def test_bad_area_lights_are_refused_naming_the_argument(build: object, match: str) -> None:
    with pytest.raises(ValueError, match=f"^{match}:"):
        build()  # type: ignore[operator]


def test_bad_types_and_settings_are_refused_naming_them() -> None:
    with pytest.raises(TypeError, match="radius"):
        brdfpy.SphereLight((0, 1, 0), "big")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="two_sided"):
        brdfpy.RectLight((0, 1, 0), (1, 0, 0), (0, 0, 1), two_sided="yes")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="base class"):
        brdfpy.AreaLight()
    scene = floor_scene(brdfpy.SphereLight((0, 1, 0), 0.2))
    for bad in (0, -1, 2**20 + 1):
        with pytest.raises(ValueError, match="area_samples"):
            scene.render(floor_camera(), 8, 8, area_samples=bad)
    with pytest.raises(TypeError, match="area_samples"):
        scene.render(floor_camera(), 8, 8, area_samples=1.5)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="area_seed"):
        scene.render(floor_camera(), 8, 8, area_seed=-1)


def test_extreme_but_valid_lights_never_give_nan() -> None:
    for light in (
        brdfpy.SphereLight((0, 1e-3, 0), 9e-4, 1e6),  # almost touching the floor
        brdfpy.SphereLight((0, 1e4, 0), 1e-3, 1e6),  # tiny and far
        brdfpy.SphereLight((0, 0, 0), 0.3, 1.0),  # cut by the floor: points inside receive nothing
        brdfpy.RectLight((0, 1e-4, 0), (1, 0, 0), (0, 0, 1), 1.0),  # just above the floor
        brdfpy.RectLight((0, 0, 0), (1, 0, 0), (0, 1, 0), 1.0, two_sided=True),  # crossing the floor
    ):
        img = render_floor(floor_scene(light), 16, area_samples=4)
        assert np.isfinite(img).all() and (img >= 0).all(), light


@pytest.mark.parametrize(
    "light",
    [
        brdfpy.SphereLight((0.3, 2.1, -0.7), 0.35, intensity=(5, 4, 3), color=(1, 0.5, 0.25)),
        brdfpy.RectLight((0.1, 1.9, 0.2), (0.7, 0.1, 0), (0, 0.05, 0.4), 3.3, two_sided=True),
        brdfpy.RectLight((0, 1, 0), (1, 0, 0), (0.3, 0, 1), color=0.5),
    ],
    ids=["sphere", "rect two-sided", "parallelogram"],
)
def test_area_lights_pickle_and_show_their_arguments(light: brdfpy.AreaLight) -> None:
    back = pickle.loads(pickle.dumps(light))
    assert type(back) is type(light)
    assert back._fields() == light._fields()
    assert (back.color, back.intensity) == (light.color, light.intensity)
    assert repr(back) == repr(light)
    assert back.incident((0, 0, 0)) == light.incident((0, 0, 0))
    assert repr(light).startswith(f"brdfpy.{type(light).__name__}(center=")
    assert "color=" in repr(light) and "radiance" not in repr(light)
    emitted = np.multiply(light.color, light.intensity)
    assert np.allclose(light.emitted, emitted)
    assert isinstance(light, brdfpy.Light)


def test_sphere_light_irradiance_is_the_point_lights() -> None:
    light = brdfpy.SphereLight((0, 3, 0), 1.0, intensity=2.0)
    l, e, d = light.incident((0, 0, 0))
    assert l == pytest.approx((0, 1, 0)) and d == pytest.approx(3.0)
    assert e == pytest.approx((2 * math.pi / 9,) * 3, rel=1e-6)  # π L sin²α, sin α = 1/3
    assert light.radius == 1.0 and light.center == (0.0, 3.0, 0.0)
    assert light.incident((0, 3.5, 0)) is None  # inside
