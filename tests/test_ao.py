"""Ambient obscurance and shadows in renders (seed 004 eqs. 12.71-12.75; ``Scene.render(ao=...,
shadows=True)``), checked against geometry computed here: an open plane has w = 1 exactly, a sphere
resting on a plane darkens it toward the contact as the obscurance integral says, and shadow rays
darken exactly the points whose segment to the light the occluder blocks.

The obscurance convention is brdfpy's documented one (``brdf-raster`` ``ao.rs``): ``w(p) = (1/pi)
int mu(d) cos(theta) domega`` with ``mu(d) = (1 - exp(-tau d/d_max))/(1 - exp(-tau))`` below ``d_max``
and 1 beyond (the seed's ``1 - exp(-tau x)`` normalised to the range ``d_max``, continuous there).
"""

from __future__ import annotations

from typing import Any

import brdfpy
import numpy as np
import pytest
from numpy.typing import NDArray

from raster_oracle import camera as ocam
from raster_oracle import geometry as og

N = 64  # image side
HEIGHT = 6.0  # orthographic view height: pixels of 6/64 world units
TOP_DOWN: dict[str, Any] = {"eye": (0, 5, 0), "target": (0, 0, 0), "up": (0, 0, -1), "height": HEIGHT}


def floor_points() -> np.ndarray:
    """World point of the floor y = 0 under every pixel of the top-down view (N, N, 3)."""
    o, _ = ocam.Camera.orthographic(**TOP_DOWN).ray(N, N)
    return o * [1, 0, 1]


def render(scene: brdfpy.Scene, **kw: Any) -> brdfpy.Image:
    return scene.render(brdfpy.Camera.orthographic(**TOP_DOWN), N, N, shading="phong", **kw, outputs="all")


def ambient_floor(size: float = 5.0, subdivisions: int = 10) -> brdfpy.Scene:
    s = brdfpy.Scene(ambient_light=1.0)
    s.add(brdfpy.plane(size, subdivisions), "lambert", ambient=1.0)  # shows k_a I_a w = w
    return s


@pytest.mark.parametrize("per_pixel", [False, True])
def test_open_plane_is_unobscured(per_pixel: bool) -> None:
    img = render(ambient_floor(), ao={"samples": 32, "per_pixel": per_pixel, "d_max": 1.0})
    covered = np.asarray(img.triangle_id) >= 0
    assert covered.sum() > N * N // 2
    np.testing.assert_allclose(np.asarray(img.hdr)[covered], 1.0, rtol=1e-6)


def mu(d: np.ndarray, tau: float, d_max: float) -> np.ndarray:
    return np.where(d < d_max, (1 - np.exp(-tau * d / d_max)) / (1 - np.exp(-tau)), 1.0)


def obscurance_near_sphere(
    p: np.ndarray, radius: float, tau: float, d_max: float, k: int = 200
) -> np.ndarray:
    """w at points ``p`` (M, 3) of the floor y = 0 under a sphere of ``radius`` resting on it at the origin,
    by a k x k midpoint rule over the cosine-weighted hemisphere (u1, u2) -> (sqrt(u1) cos 2 pi u2,
    sqrt(1 - u1), sqrt(u1) sin 2 pi u2), on which w is the plain mean of mu."""
    u = (np.arange(k) + 0.5) / k
    u1, u2 = np.meshgrid(u, u)
    s = np.sqrt(u1.ravel())
    d = np.column_stack(
        [s * np.cos(2 * np.pi * u2.ravel()), np.sqrt(1 - u1.ravel()), s * np.sin(2 * np.pi * u2.ravel())]
    )
    c = np.array([0.0, radius, 0.0])
    out = []
    for q in p:
        oc = q - c
        b = d @ oc
        disc = b * b - (oc @ oc - radius * radius)
        t = -b - np.sqrt(np.maximum(disc, 0))
        dist = np.where((disc > 0) & (t > 0), t, np.inf)
        out.append(mu(dist, tau, d_max).mean())
    return np.array(out)


@pytest.fixture(scope="module")
def sphere_on_floor() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    s = ambient_floor(5.0, 20)
    s.add(brdfpy.icosphere(4), "lambert", og.translation((0, 1, 0)), ambient=1.0)
    tau, d_max = 2.0, 2.0
    img = render(s, ao={"tau": tau, "d_max": d_max, "samples": 256, "per_pixel": True})
    ids = np.asarray(img.triangle_id)
    floor = (ids >= 0) & (ids < 800)  # the plane comes first: 2 x 20 x 20 faces
    return np.asarray(img.hdr)[..., 0].astype(float), floor, floor_points()


def test_sphere_on_a_plane_darkens_it_toward_the_contact(sphere_on_floor: Any) -> None:
    w, floor, p = sphere_on_floor
    r = np.hypot(p[..., 0], p[..., 2])
    # the floor is visible from above outside the sphere's outline (r > 1)
    near = floor & (r > 1.05) & (r < 1.3)
    far = floor & (r > 2.3) & (r < 2.5)
    assert near.any() and far.any()
    assert w[near].mean() < w[far].mean() - 0.1
    assert (w[floor] <= 1 + 1e-6).all() and (w[floor] >= 0).all()
    # obscurance falls monotonically toward the sphere (rings of 0.1)
    rings = [w[floor & (r >= a) & (r < a + 0.1)].mean() for a in np.arange(1.1, 2.4, 0.1)]
    assert np.all(np.diff(rings) > 0)


def test_obscurance_matches_the_integral_near_the_sphere(sphere_on_floor: Any) -> None:
    w, floor, p = sphere_on_floor
    r = np.hypot(p[..., 0], p[..., 2])
    pick = floor & (r > 1.05) & (r < 2.6)
    idx = np.argwhere(pick)[:: max(1, int(pick.sum()) // 40)]
    want = obscurance_near_sphere(p[idx[:, 0], idx[:, 1]], 1.0, 2.0, 2.0)
    got = w[idx[:, 0], idx[:, 1]]
    # 256 stratified (Hammersley) rays per point: error ~ a few 1/256 on this smooth integrand; the
    # level-4 icosphere lies inside the sphere by < 0.5 %, moving w by less than that (measured: 0.002)
    np.testing.assert_allclose(got, want, atol=0.01)
    # the comparison includes clearly obscured points (w is 0.88 next to the sphere's outline here)
    assert want.min() < 0.9 and want.max() > 0.99


def test_per_vertex_obscurance_is_interpolated_per_pixel() -> None:
    # per-vertex AO on a fine floor approaches the per-pixel estimate
    s = ambient_floor(5.0, 40)
    s.add(brdfpy.icosphere(3), "lambert", og.translation((0, 1, 0)), ambient=1.0)
    opts = {"tau": 2.0, "d_max": 2.0, "samples": 128}
    a = np.asarray(render(s, ao={**opts, "per_pixel": False}).hdr)[..., 0]
    b = np.asarray(render(s, ao={**opts, "per_pixel": True}).hdr)[..., 0]
    p = floor_points()
    r = np.hypot(p[..., 0], p[..., 2])
    ring = (r > 1.2) & (r < 2.4)
    assert np.abs(a[ring] - b[ring]).mean() < 0.03


# ------------------------------------------------------------------------------------------ shadows


def occluder_square(h: float = 0.5, half: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    v = np.array([[-half, h, -half], [half, h, -half], [half, h, half], [-half, h, half]])
    f = np.array([[0, 3, 2], [0, 2, 1]])  # CCW seen from above (+y)
    return v, f


def blocked(
    p: np.ndarray, to_light: np.ndarray, t_max: np.ndarray, v: np.ndarray, f: np.ndarray
) -> np.ndarray:
    """Whether the segment p + t*to_light, 0 < t < t_max, hits a triangle (Moller-Trumbore)."""
    hit = np.zeros(p.shape[:-1], bool)
    for a, b, c in v[f]:
        e1, e2 = b - a, c - a
        pv = np.cross(to_light, e2)
        det = pv @ e1
        inv = 1 / np.where(np.abs(det) > 1e-12, det, np.nan)
        s = p - a
        u = np.sum(s * pv, axis=-1) * inv
        q = np.cross(s, e1)
        w = np.sum(to_light * q, axis=-1) * inv
        t = (q @ e2) * inv
        hit |= (u >= 0) & (w >= 0) & (u + w <= 1) & (t > 1e-6) & (t < t_max)
    return hit


LIGHTS = {
    "directional": (brdfpy.DirectionalLight((1, -1, 0.3), 2.0), None),
    "point": (brdfpy.PointLight((-1.5, 2.0, 0.5), 8.0), np.array([-1.5, 2.0, 0.5])),
    "spot": (
        brdfpy.SpotLight((-1.5, 2.0, -0.5), (0.6, -1, 0.2), 8.0, inner_angle=50, outer_angle=60),
        np.array([-1.5, 2.0, -0.5]),
    ),
}


@pytest.mark.parametrize("kind", sorted(LIGHTS))
def test_shadows_fall_where_the_occluder_blocks_the_light(kind: str) -> None:
    light, pos = LIGHTS[kind]
    v, f = occluder_square()
    s = brdfpy.Scene(ambient_light=1.0)
    s.add(brdfpy.plane(5.0, 4), "lambert", ambient=0.05)
    s.add(brdfpy.Mesh(v, f, normals=np.tile([0, 1.0, 0], (4, 1))), "lambert", ambient=0.05)
    s.add_light(light)
    lit = np.asarray(render(s).hdr)[..., 0]
    img = render(s, shadows=True)
    shadowed, ids = np.asarray(img.hdr)[..., 0], np.asarray(img.triangle_id)
    p = floor_points()
    if pos is None:
        d = -np.asarray(light.direction, float)
        to_light = np.broadcast_to(d / np.linalg.norm(d), p.shape)
        t_max = np.full(p.shape[:2], np.inf)
    else:
        to_light = pos - p
        t_max = np.linalg.norm(to_light, axis=-1)
        to_light = to_light / t_max[..., None]
    want_dark = blocked(p, to_light, t_max, v, f)
    floor = (ids >= 0) & (ids < 32)
    # leave out pixels within ~1.5 px of the shadow's edge, where the pixel's exact position decides
    edge = np.zeros_like(want_dark)
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            edge |= np.roll(want_dark, (dr, dc), axis=(0, 1)) != want_dark
    check = floor & ~edge
    in_shadow = check & want_dark
    assert in_shadow.sum() > 20, "the test scene must cast a visible shadow"
    np.testing.assert_allclose(shadowed[in_shadow], 0.05, rtol=1e-5)  # ambient only
    out = check & ~want_dark
    np.testing.assert_allclose(shadowed[out], lit[out], rtol=1e-6)  # unaffected
    assert (lit[in_shadow] > 0.06).all()  # the light does reach those points without shadows


@pytest.mark.parametrize("shading", ["flat", "gouraud"])
def test_shadows_fall_per_pixel_whatever_the_shading_mode(shading: str) -> None:
    # A floor of two triangles (centroids and corners all far from the shadow) under a slanted sun, a
    # sphere above it: the floor's shadow must be where Phong shading puts it, pixel for pixel, not
    # decided once per triangle (flat) or vertex (Gouraud).
    s = brdfpy.Scene(ambient_light=0.2)
    s.add(brdfpy.plane(5.0, 1), "lambert", ambient=0.2)
    s.add(brdfpy.icosphere(3), "lambert", ambient=0.2, transform=brdfpy.transforms.translate((0, 1, 0)))
    s.add_light(brdfpy.DirectionalLight((1, -1, 0)))
    cam = brdfpy.Camera.orthographic(**TOP_DOWN)
    phong = s.render(cam, N, N, shading="phong", shadows=True, outputs="all")
    other = s.render(cam, N, N, shading=shading, shadows=True, outputs="all")
    floor = np.asarray(phong.triangle_id) < 2
    hdr_p, hdr_o = np.asarray(phong.hdr)[floor], np.asarray(other.hdr)[floor]
    assert (hdr_p[:, 0] < 0.1).sum() > 100  # a real shadow on the floor
    np.testing.assert_allclose(hdr_o, hdr_p, rtol=1e-5, atol=1e-6)


def test_renders_in_a_loop_reuse_the_bvh_and_obscurance_until_the_geometry_changes() -> None:
    # A turntable: the camera and the lights move, the geometry does not, so the BVH and the per-vertex
    # obscurance are prepared once. Moving an instance or editing a mesh prepares them again.
    def build(offset: float = 0.0) -> brdfpy.Scene:
        s = brdfpy.Scene(ambient_light=0.3)
        s.add(brdfpy.plane(5.0, 8), "lambert", ambient=0.5)
        s.add(
            brdfpy.icosphere(3), "lambert", ambient=0.5, transform=brdfpy.transforms.translate((offset, 1, 0))
        )
        s.add_light(brdfpy.DirectionalLight((1, -1, 0)))
        return s

    def shot(s: brdfpy.Scene, angle: float = 0.0) -> NDArray[np.uint8]:
        eye = (5 * np.sin(angle), 4.0, 5 * np.cos(angle))
        cam = brdfpy.Camera.perspective(eye, (0, 0, 0), fovy=40)
        return s.render(cam, 64, 48, ao={"samples": 8, "d_max": 1.0}, shadows=True).rgb

    s = build()
    shot(s)
    hits, misses = brdfpy._brdfpy.occlusion_cache_info()
    for k in range(3):
        s.lights[0] = brdfpy.DirectionalLight((1, -1, 0.2 * k))
        shot(s, 0.3 * k)
    assert brdfpy._brdfpy.occlusion_cache_info() == (hits + 3, misses)
    # Moved: prepared again, and the shadow and obscurance follow (the image of a scene built with the
    # sphere there).
    s.lights[0] = brdfpy.DirectionalLight((1, -1, 0))
    assert brdfpy._brdfpy.occlusion_cache_info() == (hits + 3, misses)
    s.instances[1].transform = brdfpy.transforms.translate((0.7, 1, 0))
    moved = shot(s)
    assert brdfpy._brdfpy.occlusion_cache_info() == (hits + 3, misses + 1)
    shot(s, 0.5)
    assert brdfpy._brdfpy.occlusion_cache_info() == (hits + 4, misses + 1)
    assert np.array_equal(moved, shot(build(0.7)))
    # An edited mesh is another mesh.
    shot(s)
    s.instances[1].mesh.flip_winding()
    shot(s)
    assert brdfpy._brdfpy.occlusion_cache_info() == (hits + 4, misses + 4)
