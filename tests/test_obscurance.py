"""Per-vertex ambient obscurance from Python (``Mesh.compute_obscurance``, issue 4), checked against values
derived here by deterministic quadrature of seed 004's integral over the hemisphere:

    w(p) = (1/pi) int mu(d(p, omega)) cos(theta) domega,
    mu(d) = (1 - exp(-tau d/d_max)) / (1 - exp(-tau))   (d < d_max),   1 beyond,

(brdfpy's documented normalisation of the seed's ``1 - exp(-tau x)`` to the range ``d_max``), with the
distances ``d`` computed analytically from the planes and spheres of each scene. brdfpy estimates ``w``
with ``samples`` cosine-weighted rays, i.e. as the mean of ``mu`` over cosine-distributed directions; its
error is then compared with the Monte-Carlo standard error ``sigma_mu / sqrt(samples)``, where
``sigma_mu`` is the standard deviation of ``mu`` under the cosine distribution, also by quadrature.
"""

from __future__ import annotations

from pathlib import Path

import brdfpy
import numpy as np
import pytest

from conftest import GIL_RELEASED_FRACTION, python_spins_during


def mu(d: np.ndarray, tau: float, d_max: float) -> np.ndarray:
    with np.errstate(invalid="ignore", over="ignore"):
        return np.where(d < d_max, np.expm1(-tau * np.minimum(d, d_max) / d_max) / np.expm1(-tau), 1.0)


def hemisphere_rule(n_theta: int = 256, n_phi: int = 1024) -> tuple[np.ndarray, np.ndarray]:
    """Directions (K, 3) around +y and weights (K,) with sum(weights * f) ~ (1/pi) int f cos(theta) domega:
    Gauss-Legendre in theta on [0, pi/2] (nodes cluster at both ends, where the integrand's kinks are
    milder), the midpoint rule in phi (periodic: spectrally accurate for smooth integrands)."""
    x, wx = np.polynomial.legendre.leggauss(n_theta)
    theta = (x + 1) * np.pi / 4
    w_theta = wx * np.pi / 4 * np.cos(theta) * np.sin(theta) / np.pi
    phi = (np.arange(n_phi) + 0.5) * 2 * np.pi / n_phi
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    dirs = np.stack([np.sin(th) * np.cos(ph), np.cos(th), np.sin(th) * np.sin(ph)], axis=-1).reshape(-1, 3)
    weights = (w_theta[:, None] * np.full(n_phi, 2 * np.pi / n_phi)).reshape(-1)
    return dirs, weights


def box_floor_distance(p: np.ndarray, dirs: np.ndarray, half: float) -> np.ndarray:
    """Distance from a point ``p`` on the floor y = -half of the open box [-half, half]^3 (no top) to the
    first wall along each direction (upper hemisphere), inf when the ray leaves through the open top."""
    d = np.full(len(dirs), np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        for axis in (0, 2):
            c = dirs[:, axis]
            wall = np.where(c > 0, (half - p[axis]) / c, np.where(c < 0, (-half - p[axis]) / c, np.inf))
            d = np.minimum(d, wall)
        top = (half - p[1]) / dirs[:, 1]
    return np.where(d < top, d, np.inf)


def floor_vertex(mesh: brdfpy.Mesh, point: tuple[float, float, float]) -> int:
    """Index of the vertex at ``point`` with normal +y (walls have their own vertices at their edges)."""
    v, n = mesh.vertices, mesh.normals
    dist = np.linalg.norm(v - np.asarray(point), axis=1) + 10 * np.linalg.norm(n - [0, 1, 0], axis=1)
    i = int(np.argmin(dist))
    assert np.allclose(v[i], point, atol=1e-6) and np.allclose(n[i], [0, 1, 0], atol=1e-6)
    return i


# --------------------------------------------------------------------------------------- analytic cases


@pytest.mark.parametrize(("tau", "d_max"), [(2.0, 1.0), (0.5, 0.3), (8.0, 5.0)])
def test_every_vertex_of_an_open_plane_has_w_exactly_one(tau: float, d_max: float) -> None:
    plane = brdfpy.plane(3.0, 12)
    w = plane.compute_obscurance(tau=tau, d_max=d_max, samples=32)
    assert w.shape == (plane.n_vertices,) and w.dtype == np.float32
    assert (w == 1.0).all()


@pytest.mark.parametrize(
    ("point", "tau", "d_max"),
    [
        ((0.0, -0.5, 0.0), 2.0, 1.0),  # bottom centre
        ((0.0, -0.5, 0.0), 0.5, 0.8),
        ((0.25, -0.5, -0.125), 2.0, 1.0),  # off centre
        ((0.375, -0.5, 0.375), 6.0, 0.5),  # near a corner
    ],
)
def test_floor_of_an_open_box_matches_the_integral(
    point: tuple[float, float, float], tau: float, d_max: float
) -> None:
    # d_max <= the box height: where a ray just clears the open top, the wall it would hit is >= 1 away, so
    # mu is continuous there (1 on both sides) and the quadrature converges fast.
    box = brdfpy.open_box(1.0, 8)
    i = floor_vertex(box, point)
    samples = 1024
    w = box.compute_obscurance(tau=tau, d_max=d_max, samples=samples, seed=3)[i]
    dirs, weights = hemisphere_rule()
    m = mu(box_floor_distance(np.asarray(point), dirs, 0.5), tau, d_max)
    exact = float(weights @ m)
    sigma = float(np.sqrt(max(weights @ m**2 - exact**2, 0.0)))
    assert abs(weights.sum() - 1) < 1e-12
    assert 0.05 < exact < 0.99  # the case is not trivial
    # Monte-Carlo standard error of the mean of `samples` values of mu; the stratified set does better.
    assert abs(w - exact) < 3 * sigma / np.sqrt(samples) + 1e-4, (w, exact, sigma)


def test_box_floor_converges_with_the_sample_count() -> None:
    box = brdfpy.open_box(1.0, 2)
    i = floor_vertex(box, (0.0, -0.5, 0.0))
    dirs, weights = hemisphere_rule()
    exact = float(weights @ mu(box_floor_distance(np.array([0.0, -0.5, 0.0]), dirs, 0.5), 2.0, 1.0))
    errors = [
        np.mean([abs(box.compute_obscurance(d_max=1.0, samples=s, seed=k)[i] - exact) for k in range(8)])
        for s in (16, 256, 4096)
    ]
    assert errors[2] < errors[0] / 8, errors  # 1/sqrt(S) alone would give /16 over 256x the samples
    assert errors[2] < 2e-3


def sphere_on_plane(level: int = 4, size: float = 4.0, cells: int = 40) -> tuple[brdfpy.Mesh, int, float]:
    """A unit sphere resting on the plane y = 0 (touching near the origin) and the plane, as one mesh;
    returns it, the number of plane vertices (the first ones) and the height of the sphere's centre."""
    plane = brdfpy.plane(size, cells)
    ball = brdfpy.icosphere(level)
    bv = ball.vertices.astype(np.float64)
    lift = 1e-4 - bv[:, 1].min()  # lowest vertex just above the floor
    bv[:, 1] += lift
    v = np.concatenate([plane.vertices, bv])
    f = np.concatenate([plane.faces, ball.faces + plane.n_vertices])
    n = np.concatenate([plane.normals, ball.normals])
    return brdfpy.Mesh(v, f, n), plane.n_vertices, lift


def test_a_sphere_resting_on_a_plane_darkens_it_toward_the_contact() -> None:
    mesh, n_plane, centre_y = sphere_on_plane()
    tau, d_max = 2.0, 1.5
    w = mesh.compute_obscurance(tau=tau, d_max=d_max, samples=256)
    floor = mesh.vertices[:n_plane]
    r = np.hypot(floor[:, 0], floor[:, 2])
    wf = w[:n_plane]
    # Mean w in rings around the contact rises with the distance from it, up to 1 well outside the
    # sphere's reach (beyond sqrt((1 + d_max)^2 - 1) nothing within d_max is above the floor).
    rings = [wf[(r >= a) & (r < a + 0.25)].mean() for a in np.arange(0.0, 1.75, 0.25)]
    assert np.all(np.diff(rings) > 0), rings
    assert rings[0] < 0.5
    reach = np.sqrt((1 + d_max) ** 2 - 1)
    assert (wf[r > reach + 0.05] == 1.0).all()

    # ... and matches the integral with exact ray-sphere distances (the level-4 sphere's facets sag by
    # < 2e-3, far below the tolerance).
    dirs, weights = hemisphere_rule(128, 512)
    c = np.array([0.0, centre_y, 0.0])
    picked = np.flatnonzero((r > 0.1) & (r < 2.0))[::7]
    for i in picked:
        oc = floor[i] - c
        b = dirs @ oc
        disc = b * b - (oc @ oc - 1.0)
        t = -b - np.sqrt(np.maximum(disc, 0))
        d = np.where((disc > 0) & (t > 0), t, np.inf)
        m = mu(d, tau, d_max)
        exact = weights @ m
        sigma = np.sqrt(max(weights @ m**2 - exact**2, 0))
        assert abs(w[i] - exact) < 4 * sigma / 16 + 5e-3, (floor[i], w[i], exact)


def test_values_lie_in_unit_interval_and_creases_are_darker() -> None:
    cow = brdfpy.builtin_mesh("cow")
    w = cow.compute_obscurance(d_max=0.2, samples=64)
    assert ((w >= 0) & (w <= 1)).all()
    # Convex parts of a closed mesh see more sky: the vertex highest on the back is nearly open; the
    # mean over the mesh is clearly below 1 (legs, udder, ears), and larger d_max means more occlusion.
    top = int(np.argmax(cow.vertices[:, 1]))
    assert w[top] > 0.9
    assert w.mean() < 0.97
    assert cow.compute_obscurance(d_max=0.4, samples=64).mean() < w.mean()


def test_a_closed_mesh_seen_from_inside_is_enclosed() -> None:
    # The CC0 cow of tests/data (closed, outward) and the same surface with its normals turned inward:
    # from inside, every ray meets the far wall within the cow's length (~1.2 at most), so with d_max = 5
    # each mu is at most mu(1.25) = (1 - e^(-2 * 1.25/5))/(1 - e^(-2)) ~ 0.455 — except at a handful of
    # needle tips (tail, horns) whose vertex normal points out of the thin part.
    cow = brdfpy.load_mesh(Path(__file__).parent / "data" / "garland_cow.ply")
    inside = cow.copy().flip_winding()
    w_out = cow.compute_obscurance(d_max=5.0, samples=32)
    w_in = inside.compute_obscurance(d_max=5.0, samples=32)
    bound = float(mu(np.array([1.25]), 2.0, 5.0)[0])
    assert (w_in <= bound + 1e-6).mean() > 0.999
    assert w_in.mean() < 0.6 * w_out.mean()


def test_larger_tau_counts_far_occluders_less() -> None:
    # mu(d) = (1 - e^(-tau d/d_max))/(1 - e^(-tau)) increases with tau for every d in (0, d_max): the
    # same geometry at larger tau is less obscured.
    box = brdfpy.open_box(1.0, 4)
    ws = [box.compute_obscurance(tau=t, d_max=1.0, samples=128).mean() for t in (0.5, 2.0, 8.0)]
    assert ws[0] < ws[1] < ws[2], ws


def test_zero_normal_vertex_is_unobscured() -> None:
    # An isolated vertex (no face) has a zero normal: no hemisphere, w = 1 by definition.
    v = [[0, 0, 0], [1, 0, 0], [0, 0, -1], [5, 5, 5]]
    m = brdfpy.Mesh(v, [[0, 1, 2]])
    assert np.allclose(m.normals[3], 0)
    assert m.compute_obscurance(d_max=1.0)[3] == 1.0


# --------------------------------------------------------------------------------------- determinism


def test_bit_identical_at_any_thread_count_and_repeatable(restore_threads: None) -> None:
    cow = brdfpy.builtin_mesh("cow")
    results = []
    for n in (1, 2, 4, 3):
        brdfpy.set_num_threads(n)
        results.append(cow.compute_obscurance(d_max=0.3, samples=32, seed=9))
    for r in results[1:]:
        assert np.array_equal(r, results[0])
    other_seed = cow.compute_obscurance(d_max=0.3, samples=32, seed=10)
    assert not np.array_equal(other_seed, results[0])
    assert abs(other_seed.mean() - results[0].mean()) < 0.01


def test_raycaster_obscurance_equals_compute_obscurance() -> None:
    cow = brdfpy.builtin_mesh("cow")
    w = cow.compute_obscurance(tau=3.0, d_max=0.25, samples=16, seed=4)
    w2 = brdfpy.RayCaster(cow).obscurance(cow.vertices, cow.normals, tau=3.0, d_max=0.25, samples=16, seed=4)
    assert np.array_equal(w, w2)


def test_default_d_max_is_a_quarter_of_the_diagonal() -> None:
    cow = brdfpy.builtin_mesh("cow")
    lo, hi = cow.bounds()
    d = 0.25 * float(np.linalg.norm(hi - lo))
    assert np.array_equal(cow.compute_obscurance(samples=8), cow.compute_obscurance(d_max=d, samples=8))


def test_releases_the_gil(one_thread: None) -> None:
    mesh = brdfpy.icosphere(5)
    speed, _ = python_spins_during(lambda: mesh.compute_obscurance(d_max=0.5, samples=128))
    assert speed > GIL_RELEASED_FRACTION, speed  # held, the loop would stand still while it runs


# --------------------------------------------------------------------------------------- stored values


def test_stored_obscurance_round_trip_and_invalidation() -> None:
    cow = brdfpy.builtin_mesh("cow")
    assert cow.obscurance is None
    w = cow.compute_obscurance(d_max=0.3, samples=8)
    assert cow.obscurance is None  # not stored unless asked
    w = cow.compute_obscurance(d_max=0.3, samples=8, store=True)
    assert np.array_equal(cow.obscurance, w)
    assert not cow.obscurance.flags.writeable
    assert np.array_equal(cow.copy().obscurance, w)
    assert cow.transformed(np.eye(4)).obscurance is None
    cow.compute_normals("area")
    assert cow.obscurance is None  # normals changed: the hemispheres moved
    cow.obscurance = w
    cow.flip_winding()
    assert cow.obscurance is None
    cow.obscurance = np.linspace(0, 1, cow.n_vertices)
    assert cow.obscurance.dtype == np.float32
    cow.obscurance = None
    assert cow.obscurance is None


@pytest.mark.parametrize(
    ("value", "exc", "word"),
    [
        (np.ones(3), ValueError, "shape"),
        (np.full(4, 1.5), ValueError, "[0, 1]"),
        (np.array([0.5, np.nan, 0.5, 0.5]), ValueError, "vertex 1"),
        (np.array(["a"] * 4), TypeError, "dtype"),
        ("0.5", TypeError, "obscurance"),
    ],
)
def test_bad_stored_obscurance(value: object, exc: type[Exception], word: str) -> None:
    m = brdfpy.Mesh([[0, 0, 0], [1, 0, 0], [0, 0, -1], [1, 0, -1]], [[0, 1, 2], [1, 3, 2]])
    with pytest.raises(exc, match="obscurance") as e:
        m.obscurance = value
    assert word in str(e.value)


N = 48
TOP_DOWN = {"eye": (0, 5, 0), "target": (0, 0, 0), "up": (0, 0, -1), "height": 2.0}


def ambient_only(mesh: brdfpy.Mesh) -> brdfpy.Scene:
    s = brdfpy.Scene(ambient_light=1.0)
    s.add(mesh, "lambert", ambient=1.0)  # the image shows k_a I_a w = w
    return s


def test_render_uses_stored_values_interpolated_over_the_faces() -> None:
    # A stored w that is linear in x on an open plane (whose estimated w would be 1 everywhere): the
    # render must show exactly that linear function, as interpolation of a linear function is exact.
    plane = brdfpy.plane(2.0, 4)
    x = plane.vertices[:, 0].astype(np.float64)
    plane.obscurance = 0.2 + 0.3 * (x + 1)  # 0.2 .. 0.8
    scene = ambient_only(plane)
    cam = brdfpy.Camera.orthographic(**TOP_DOWN)
    stored = np.asarray(scene.render(cam, N, N, ao={"stored": True, "d_max": 1.0}, outputs="all").hdr)[..., 0]
    estimated = np.asarray(scene.render(cam, N, N, ao={"d_max": 1.0}, outputs="all").hdr)[..., 0]
    px = (np.arange(N) + 0.5) / N * 2 - 1  # world x of each pixel centre column (orthographic, 2 wide)
    np.testing.assert_allclose(stored, np.broadcast_to(0.2 + 0.3 * (px + 1), (N, N)), atol=2e-6)
    np.testing.assert_allclose(estimated, 1.0, rtol=1e-6)


def test_stored_flag_without_stored_values_is_an_error_not_a_silent_estimate() -> None:
    # The mesh is stored after Scene.add took its snapshot: the scene's copy has nothing stored.
    plane = brdfpy.plane()
    scene = ambient_only(plane)
    plane.compute_obscurance(d_max=1.0, store=True)
    cam = brdfpy.Camera.orthographic(**TOP_DOWN)
    with pytest.raises(ValueError, match="stored"):
        scene.render(cam, 8, 8, ao={"stored": True}, outputs="all")
    scene.instances[0].mesh.compute_obscurance(d_max=1.0, store=True)  # the instance's own mesh
    assert np.asarray(scene.render(cam, 8, 8, ao={"stored": True}, outputs="all").hdr).max() > 0


def test_render_with_stored_values_equals_render_estimating_them() -> None:
    cow = brdfpy.builtin_mesh("cow")
    opts = {"tau": 2.0, "d_max": 0.3, "samples": 32, "seed": 5}
    cow.compute_obscurance(**opts, store=True)
    scene = ambient_only(cow)
    cam = brdfpy.Camera.perspective((0.0, 0.3, 1.8), target=(0, 0, 0))
    for shading in ("gouraud", "phong"):
        a = np.asarray(scene.render(cam, 80, 60, shading, ao=opts, outputs="all").hdr)
        b = np.asarray(scene.render(cam, 80, 60, shading, ao={**opts, "stored": True}, outputs="all").hdr)
        assert (a < 0.999).any()
        np.testing.assert_allclose(a, b, atol=1e-6)


def test_render_mixes_stored_and_estimated_instances_and_keeps_shadows() -> None:
    # Instance 0 stores w = 0.25 everywhere; instance 1 (no stored values) is estimated; a directional
    # light at 45 degrees casts instance 0's shadow on instance 1, beside it in the top-down view.
    small = brdfpy.plane(0.5, 2)
    small.obscurance = np.full(small.n_vertices, 0.25)
    scene = brdfpy.Scene(ambient_light=1.0)
    lift = np.eye(4)
    lift[1, 3] = 0.5
    scene.add(small, "lambert", lift, ambient=0.5)
    scene.add(brdfpy.plane(2.0, 8), "lambert", ambient=0.5)
    scene.add_light(brdfpy.DirectionalLight((1, -1, 0)))
    cam = brdfpy.Camera.orthographic(**TOP_DOWN)
    img = scene.render(cam, N, N, ao={"stored": True, "d_max": 0.1}, shadows=True, outputs="all")
    hdr, ids = np.asarray(img.hdr)[..., 0], np.asarray(img.triangle_id)
    top = ids < small.n_faces
    direct = 0.8 / np.pi * np.sqrt(0.5)  # lambert albedo 0.8, n.l = cos 45 degrees, irradiance 1
    # Top plane: ambient 0.5 * stored w 0.25 + direct light (nothing above it).
    np.testing.assert_allclose(hdr[top], 0.5 * 0.25 + direct, rtol=1e-5)
    # Floor: its own w is 1 (d_max 0.1 < the 0.5 gap); in the top plane's shadow, x in [0, 0.5] beside it
    # (a 0.5 x 0.5 square shifted by 0.5 along +x: the light travels along +x as it falls), only ambient.
    floor = ~top & (ids >= 0)
    px = (np.arange(N) + 0.5) / N * 2 - 1
    x, z = np.broadcast_to(px, (N, N)), np.broadcast_to(px[:, None], (N, N))
    shadow = (x > 0.25 + 0.03) & (x < 0.75 - 0.03) & (abs(z) < 0.25 - 0.03)
    lit = floor & ~((x > 0.25 - 0.03) & (x < 0.75 + 0.03) & (abs(z) < 0.25 + 0.03))
    assert shadow.sum() > 50
    np.testing.assert_allclose(hdr[shadow & floor], 0.5, rtol=1e-5)
    np.testing.assert_allclose(hdr[lit], 0.5 + direct, rtol=1e-5)


# --------------------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("kwargs", "exc", "name"),
    [
        ({"tau": 0.0}, ValueError, "tau"),
        ({"tau": -1.0}, ValueError, "tau"),
        ({"tau": float("nan")}, ValueError, "tau"),
        ({"tau": float("inf")}, ValueError, "tau"),
        ({"d_max": 0.0}, ValueError, "d_max"),
        ({"d_max": -2.0}, ValueError, "d_max"),
        ({"d_max": float("nan")}, ValueError, "d_max"),
        ({"d_max": 1e300}, ValueError, "d_max"),  # beyond float32
        ({"samples": 0}, ValueError, "samples"),
        ({"samples": 65537}, ValueError, "samples"),
        ({"samples": 2.5}, TypeError, "samples"),
        ({"samples": True}, TypeError, "samples"),
        ({"seed": -1}, ValueError, "seed"),
        ({"seed": 2**64}, ValueError, "seed"),
        ({"tau": "2"}, TypeError, "tau"),
        ({"d_max": None, "tau": None}, TypeError, "tau"),
    ],
)
def test_bad_arguments_raise_naming_the_argument(kwargs: dict, exc: type[Exception], name: str) -> None:
    with pytest.raises(exc, match=name):
        brdfpy.plane().compute_obscurance(**kwargs)


@pytest.mark.parametrize(
    ("args", "name"),
    [((2.0, 0.0, 64, 0), "d_max"), ((float("nan"), 1.0, 64, 0), "tau"), ((2.0, 1.0, 0, 0), "samples")],
)
def test_compiled_module_checks_too(args: tuple, name: str) -> None:
    # The private compiled function checks its arguments itself: a direct call cannot misbehave either.
    with pytest.raises(ValueError, match=name):
        brdfpy._brdfpy.mesh_obscurance(brdfpy.plane()._m, *args)


def test_degenerate_faces_are_skipped_not_an_error() -> None:
    # A zero-area face (repeated vertex) occludes nothing; the other vertices are still computed.
    v = [[0, 0, 0], [1, 0, 0], [0, 0, -1], [0.2, 0.1, -0.2]]
    m = brdfpy.Mesh(v, [[0, 1, 2], [3, 3, 3]])
    w = m.compute_obscurance(d_max=1.0)
    assert w[0] == 1.0 and np.isfinite(w).all()


# --------------------------------------------------------------------------------------- command line


def test_cli_renders_a_user_mesh_with_ao_and_shadows(tmp_path) -> None:
    # The CC0 cow of tests/data on the CLI's floor: obscurance only ever darkens (w <= 1 scales the
    # ambient term, and tone mapping is monotone), shadows only ever darken, and both visibly do.
    from brdfpy import cli
    from PIL import Image

    mesh = str(Path(__file__).parent / "data" / "garland_cow.ply")
    images = {}
    for name, extra in {
        "both": ["--ao", "--shadows"],
        "shadows": ["--shadows"],
        "neither": ["--no-shadows"],
    }.items():
        out = tmp_path / f"{name}.png"
        args = ["render", "--mesh", mesh, "--size", "160x90", "--samples", "1", "-q", "-o", str(out)]
        assert cli.main([*args, *extra]) == 0
        with Image.open(out) as im:
            images[name] = np.asarray(im).astype(int)
    both, shadows, neither = images["both"], images["shadows"], images["neither"]
    assert (both <= shadows).all() and (both < shadows).any(axis=2).sum() > 500
    assert (shadows <= neither).all() and (shadows < neither).any(axis=2).sum() > 500
