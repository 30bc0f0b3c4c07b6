"""Self-checks of the reference rasterizer (``tests/raster_oracle``) against SCENE.md's figures and
closed-form geometry, so that a disagreement with brdfpy can be blamed on the right side."""

from __future__ import annotations

import numpy as np
import pytest

from oracle import tonemap as otm
from raster_oracle import camera as ocam
from raster_oracle import geometry as og
from raster_oracle import raster as oraster
from raster_oracle import raycast, scene
from raster_oracle.clip import clip_triangle

LAMBERT = oraster.Material("lambert", {"kd": (0.5, 0.5, 0.5)})


def test_camera_matrices_are_scene_md() -> None:
    cam = scene.camera()
    v = cam.view()
    want_v = np.eye(4)
    want_v[2, 3] = -3.0
    np.testing.assert_allclose(v, want_v, atol=1e-15)
    p = cam.projection(16 / 9)
    assert p[0, 0] == pytest.approx(1.357995, abs=1e-6)
    assert p[1, 1] == pytest.approx(2.414214, abs=1e-6)
    assert p[3, 2] == -1 and p[3, 3] == 0
    # the near and far planes land on NDC z = -1 and +1
    for z, want in ((-0.1, -1.0), (-100.0, 1.0)):
        c = p @ [0, 0, z, 1]
        assert c[2] / c[3] == pytest.approx(want)


def test_orthographic_maps_the_view_volume_to_the_ndc_cube() -> None:
    cam = ocam.Camera.orthographic((1, 2, 5), (1, 2, 0), height=4.0, near=1.0, far=9.0)
    m = cam.view_projection(2.0)
    for world, ndc in (((1 + 4, 2 + 2, 4), (1, 1, -1)), ((1 - 4, 2 - 2, -4), (-1, -1, 1))):
        c = m @ [*world, 1.0]
        np.testing.assert_allclose(c[:3] / c[3], ndc, atol=1e-12)


def test_check_values_of_scene_md() -> None:
    pts = np.array([[0, 0, 1], [0.5, 0.5, 0.707107], [-0.6, -0.6, 0.529150]])
    n = pts / np.linalg.norm(pts, axis=1, keepdims=True)
    c = oraster.illuminate(scene.material(), pts, n, scene.camera(), scene.lights(), 1.0)
    np.testing.assert_allclose(c[0], [0.810225, 0.311365, 0.211593], atol=2e-6)
    np.testing.assert_allclose(c[1], [2.1459, 0.8408, 0.5798], atol=2e-4)
    np.testing.assert_allclose(c[2], [0.04, 0.015, 0.01], atol=1e-12)
    assert otm.to_uint8(c).tolist() == [[232, 151, 127], [255, 236, 200], [56, 33, 25]]


@pytest.mark.slow
def test_ray_cast_sphere_covers_scene_md_pixel_count() -> None:
    _, hit = raycast.sphere(scene.camera(), 1920, 1080, scene.material(), scene.lights())
    assert int(hit.sum()) == 667_440


def test_ray_cast_sphere_coverage_at_small_size_is_the_projected_disc() -> None:
    # the silhouette of a unit sphere seen from distance 3 is a circle of angular radius asin(1/3)
    w, h = 64, 48
    _, hit = raycast.sphere(scene.camera(), w, h, scene.material(), scene.lights())
    f = 1 / np.tan(np.deg2rad(22.5))
    r_px = np.tan(np.arcsin(1 / 3)) * f * h / 2
    c, r = np.meshgrid(np.arange(w) + 0.5 - w / 2, np.arange(h) + 0.5 - h / 2)
    np.testing.assert_array_equal(hit, np.hypot(c, r) < r_px)


def test_icosahedron_and_subdivision_follow_scene_md() -> None:
    v, f = og.icosphere(2)
    assert len(v) == 10 * 16 + 2 and len(f) == 20 * 16
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 1, atol=1e-15)
    assert np.all(np.sum(og.face_cross(v, f) * v[f].mean(axis=1), axis=1) > 0)  # CCW from outside
    _, f1 = og.icosphere(1)
    a, b, c = og.icosahedron()[1][0]
    assert f1[0][0] == a and f1[1][0] == b and f1[2][0] == c  # children of face 0 first


def test_rasterized_icosphere_agrees_with_the_ray_cast_sphere() -> None:
    v, f = og.icosphere(4)
    sc = oraster.Scene([oraster.Instance(v, f, scene.material(), normals=v)], scene.lights())
    fr = oraster.render(sc, scene.camera(), 96, 64)
    img, hit = raycast.sphere(scene.camera(), 96, 64, scene.material(), scene.lights())
    assert (fr.covered != hit).sum() <= 4
    both = fr.covered & hit
    diff = np.abs(fr.rgb8().astype(int) - otm.to_uint8(img).astype(int))[both]
    assert diff.max() <= 3 and diff.mean() < 0.2


@pytest.mark.parametrize("kind", ["grid", "fan"])
@pytest.mark.parametrize("seed", range(3))
def test_reference_is_watertight_on_screen_tilings(kind: str, seed: int) -> None:
    rng = np.random.default_rng(seed)
    cam = ocam.Camera.perspective(rng.normal(size=3), rng.normal(size=3), fovy=60)
    v, f = og.screen_tiling(kind, rng, cam, 40 / 30)
    count = oraster.coverage_count(v, f, cam, 40, 30)
    assert count.max() == 1 and count.min() == 1


def test_top_left_rule_on_pixel_aligned_edges() -> None:
    # vertices on pixel centres: every shared edge passes through sample points
    v, f = og.grid(4, 4)
    cam = ocam.Camera.orthographic((0, 0, 1), (0, 0, 0), height=2.0 * 16 / 15)  # vertices on centres
    count = oraster.coverage_count(v, f, cam, 16, 16)
    assert count.max() == 1
    # the outer boundary: samples on the mesh's left and top edges are covered, right and bottom not
    assert count[0, 0] == 1 and count[15, 15] == 0 and count[0, 15] == 0 and count[15, 0] == 0


def test_near_clipping_keeps_the_visible_part() -> None:
    cam = scene.camera()
    vp = cam.view_projection(1.0)
    tri = np.array([[0.0, -0.5, 0.0], [0.5, 0.5, 0.0], [0.0, 0.0, 5.0]])  # last vertex behind the eye
    clip = np.column_stack([tri, np.ones(3)]) @ vp.T
    pieces = clip_triangle(clip, np.eye(3))
    assert len(pieces) == 2
    for pos, beta in pieces:
        assert np.all(pos[:, 2] + pos[:, 3] >= -1e-12)
        np.testing.assert_allclose(beta.sum(axis=1), 1)
        np.testing.assert_allclose(beta @ clip, pos, atol=1e-12)


def test_perspective_correct_interpolation_differs_from_affine() -> None:
    # a floor seen at a grazing angle: the interpolated normal must follow the surface, not the screen
    v = np.array([[-2, 0, 1], [2, 0, 1], [2, 0, -12], [-2, 0, -12]], float)
    f = np.array([[0, 1, 2], [0, 2, 3]])
    n = np.array([[0, 1, 0], [1, 1, 0], [0, 1, 1], [-1, 1, 0]], float)
    sc = oraster.Scene([oraster.Instance(v, f, LAMBERT, normals=n)], [])
    cam = ocam.Camera.perspective((0, 1, 3), (0, 0, -3), fovy=60)
    a = oraster.render(sc, cam, 32, 24, "phong")
    b = oraster.render(sc, cam, 32, 24, "phong", perspective_correct=False)
    both = a.covered & b.covered
    assert np.max(np.abs(a.normal - b.normal)[both]) > 0.1
    # the perspective-correct world position lies on the plane y = 0 and on the pixel's ray
    o, d = cam.ray(32, 24)
    t = -o[..., 1] / d[..., 1]
    hitp = o + t[..., None] * d
    np.testing.assert_allclose(a.position[a.covered], hitp[a.covered], atol=0.05)


def test_quadratic_normal_is_the_seed_edge_formula_on_edges() -> None:
    rng = np.random.default_rng(3)
    p = rng.normal(size=(3, 3))
    n = og._unit_rows(rng.normal(size=(3, 3)))
    s = np.linspace(0, 1, 7)
    beta = np.column_stack([1 - s, s, np.zeros_like(s)])
    got = oraster.quadratic_normal(beta, p, n)
    d = p[1] - p[0]
    b = 3 * ((n[0] + n[1]) @ d) / (d @ d) * d
    a = n[1] - n[0] - b
    want = n[0] + s[:, None] * a + s[:, None] ** 2 * b
    np.testing.assert_allclose(got, want / np.linalg.norm(want, axis=1, keepdims=True), atol=1e-12)
    # the property that defines b: the mean of n(s) along the edge is perpendicular to it
    mean = n[0] + a / 2 + b / 3
    assert abs(mean @ d) < 1e-12
