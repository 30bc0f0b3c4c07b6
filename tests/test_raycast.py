"""Ray queries from Python (``brdfpy.RayCaster``, issue 4) against a brute-force Moller-Trumbore test in
float64 NumPy over every triangle: the same hits and misses, the same triangles, the same distances, on
random triangle soups and random indexed meshes — except for rays that pass within a hair of a triangle's
edge or hit two triangles at nearly the same distance, where float32 and float64 may rightly disagree
(such rays are counted and must be rare). Plus the properties the BVH documents: any-hit agrees with
closest-hit on every ray, a closed mesh is watertight, degenerate triangles are never hit, triangle ids run
through the meshes of a scene in order, and results do not depend on the number of threads.
"""

from __future__ import annotations

import brdfpy
import numpy as np
import pytest

#: Rays passing closer than this (in barycentric units) to an edge of any triangle they cross are not
#: compared: the float32 watertight test and float64 Moller-Trumbore may decide such grazes differently.
EDGE = 1e-4
#: Closest hits closer than this (relative) to another triangle's hit on the same ray are not compared for
#: the triangle's identity (intersecting triangles of a soup meet along lines).
TIE = 1e-4


def moller_trumbore(
    tris: np.ndarray, o: np.ndarray, d: np.ndarray, t_min: np.ndarray, t_max: np.ndarray
) -> dict[str, np.ndarray]:
    """Every ray against every triangle (float64; Moller & Trumbore 1997). ``tris`` (F, 3, 3), ``o``, ``d``
    (N, 3), bounds (N,). Returns the closest hit (t, triangle, u, v; inf / -1 on a miss) and, per ray,
    whether it is ``clean``: no triangle edge within EDGE of where it crosses a triangle's plane inside
    the segment, no near-tie for the closest hit, no hit near the ends of the segment, no grazing plane."""
    a, b, c = (tris[:, k][None] for k in range(3))
    e1, e2 = b - a, c - a
    dd = d[:, None, :]
    p = np.cross(dd, e2)
    det = np.sum(e1 * p, axis=-1)
    area2 = np.linalg.norm(np.cross(e1, e2), axis=-1)
    grazing = np.abs(det) <= 1e-6 * area2 * np.linalg.norm(dd, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        s = o[:, None, :] - a
        u = np.sum(s * p, axis=-1) * inv
        q = np.cross(s, e1)
        v = np.sum(dd * q, axis=-1) * inv
        t = np.sum(e2 * q, axis=-1) * inv
    margin = np.minimum(np.minimum(u, v), 1 - u - v)
    lo, hi = t_min[:, None], t_max[:, None]
    in_range = (t >= lo) & (t <= hi) & ~grazing & (area2 > 0)
    hit = in_range & (margin >= 0)
    tt = np.where(hit, t, np.inf)
    tri = np.argmin(tt, axis=1)
    best = tt[np.arange(len(o)), tri]
    found = np.isfinite(best)
    clean = ~(in_range & (np.abs(margin) < EDGE)).any(axis=1)
    clean &= ~((grazing & (area2 > 0)).any(axis=1))
    # No crossing of any plane near the ends of the segment (where t >= t_min / t <= t_max may flip).
    scale = np.maximum(np.abs(t), 1.0)
    near_end = (np.abs(t - lo) < 1e-4 * scale) | (np.abs(t - hi) < 1e-4 * scale)
    clean &= ~(near_end & (margin > -EDGE) & ~grazing).any(axis=1)
    second = np.sort(tt, axis=1)[:, 1] if tt.shape[1] > 1 else np.full(len(o), np.inf)
    with np.errstate(invalid="ignore"):  # inf - inf on misses: NaN, compares False
        clean &= ~(found & (second - best <= TIE * np.maximum(best, 1e-3)))
    return {
        "t": best,
        "triangle": np.where(found, tri, -1),
        "u": np.where(found, u[np.arange(len(o)), tri], 0.0),
        "v": np.where(found, v[np.arange(len(o)), tri], 0.0),
        "clean": clean,
    }


def random_soup(rng: np.random.Generator, n: int) -> brdfpy.Mesh:
    """``n`` random triangles of random sizes and orientations in [-1, 1]^3 (overlapping, intersecting)."""
    centres = rng.uniform(-1, 1, (n, 1, 3))
    corners = centres + rng.normal(0, 0.25, (n, 3, 3))
    return brdfpy.Mesh(corners.reshape(-1, 3), np.arange(3 * n).reshape(n, 3))


def random_indexed(rng: np.random.Generator) -> brdfpy.Mesh:
    """A closed, bumpy indexed mesh: an icosphere with each vertex moved radially at random."""
    ico = brdfpy.icosphere(3)
    r = rng.uniform(0.6, 1.3, (ico.n_vertices, 1))
    return brdfpy.Mesh(ico.vertices * r, ico.faces)


def random_rays(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    o = rng.uniform(-2, 2, (n, 3))
    d = rng.normal(size=(n, 3))
    d *= rng.uniform(0.5, 2.0, (n, 1)) / np.linalg.norm(d, axis=1, keepdims=True)  # not unit length
    return o.astype(np.float32), d.astype(np.float32)


def triangles(mesh: brdfpy.Mesh) -> np.ndarray:
    return mesh.vertices.astype(np.float64)[mesh.faces.astype(np.int64)]


def compare(mesh: brdfpy.Mesh, o: np.ndarray, d: np.ndarray, t_min: np.ndarray, t_max: np.ndarray) -> None:
    rc = brdfpy.RayCaster(mesh)
    ref = moller_trumbore(triangles(mesh), o.astype(np.float64), d.astype(np.float64), t_min, t_max)
    got = rc.closest_hit(o, d, t_min.astype(np.float32), t_max.astype(np.float32))
    any_ = rc.any_hit(o, d, t_min.astype(np.float32), t_max.astype(np.float32))
    keep = ref["clean"]
    assert keep.mean() > 0.9, keep.mean()  # the comparison is not vacuous
    found = ref["triangle"] >= 0
    assert 0.1 < found[keep].mean() < 0.9  # both hits and misses are exercised
    np.testing.assert_array_equal(got.hit[keep], found[keep])
    np.testing.assert_array_equal(any_[keep], found[keep])
    h = keep & found
    np.testing.assert_array_equal(got.triangle[h], ref["triangle"][h])
    # 1e-5 relative; plus 4e-6 absolute for hits a hair from the origin, where float32 rounding of the
    # coordinates (up to 4 here: 2^-24 * 4 ~ 2.4e-7 each, a few of them per test) dominates.
    np.testing.assert_allclose(got.t[h], ref["t"][h], rtol=1e-5, atol=4e-6)
    np.testing.assert_allclose(got.u[h], ref["u"][h], atol=1e-5)
    np.testing.assert_allclose(got.v[h], ref["v"][h], atol=1e-5)
    assert np.isinf(got.t[~got.hit]).all() and (got.u[~got.hit] == 0).all()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_closest_and_any_hit_match_brute_force_on_random_soups(seed: int) -> None:
    rng = np.random.default_rng(seed)
    mesh = random_soup(rng, 300)
    o, d = random_rays(rng, 3000)
    compare(mesh, o, d, np.zeros(len(o)), np.full(len(o), np.inf))


@pytest.mark.parametrize("seed", [3, 4])
def test_closest_and_any_hit_match_brute_force_on_random_indexed_meshes(seed: int) -> None:
    rng = np.random.default_rng(seed)
    mesh = random_indexed(rng)
    o, d = random_rays(rng, 1500)
    compare(mesh, o, d, np.zeros(len(o)), np.full(len(o), np.inf))


def test_ray_segments_match_brute_force() -> None:
    # Per-ray t_min and t_max: hits outside [t_min, t_max] do not count, for either query.
    rng = np.random.default_rng(5)
    mesh = random_soup(rng, 200)
    o, d = random_rays(rng, 3000)
    t_min = rng.uniform(0, 1.0, len(o))
    t_max = t_min + rng.uniform(0, 3.0, len(o))
    compare(
        mesh, o, d, t_min.astype(np.float32).astype(np.float64), t_max.astype(np.float32).astype(np.float64)
    )


def test_any_hit_agrees_with_closest_hit_on_every_ray() -> None:
    # Including the rays at edges the brute-force comparison leaves out: one triangle test decides both.
    rng = np.random.default_rng(6)
    mesh = random_soup(rng, 500)
    rc = brdfpy.RayCaster(mesh)
    o, d = random_rays(rng, 20000)
    t_max = rng.uniform(0, 4, len(o)).astype(np.float32)
    np.testing.assert_array_equal(rc.any_hit(o, d, t_max=t_max), rc.closest_hit(o, d, t_max=t_max).hit)


def test_a_closed_mesh_is_watertight_even_through_its_vertices_and_edges() -> None:
    # Rays from inside a closed sphere always hit it, also when aimed exactly at a vertex or at the
    # midpoint of an edge, where a non-watertight test can let a ray slip between the triangles.
    ico = brdfpy.icosphere(3)
    rc = brdfpy.RayCaster(ico)
    v, f = ico.vertices, ico.faces
    rng = np.random.default_rng(7)
    origins = rng.uniform(-0.3, 0.3, (500, 3)).astype(np.float32)
    edges = (v[f[:, 0]] + v[f[:, 1]]) / 2
    for targets in (v, edges):
        pick = targets[rng.integers(0, len(targets), len(origins))]
        assert rc.any_hit(origins, pick - origins).all()
        hits = rc.closest_hit(origins, pick - origins)
        assert hits.hit.all()
        np.testing.assert_allclose(hits.t, 1.0, atol=1e-5)  # the target is on the surface at t = 1


def test_hit_points_and_barycentrics_are_consistent() -> None:
    # origin + t d lies on the triangle hit, at the point its barycentrics (1 - u - v, u, v) describe.
    rng = np.random.default_rng(8)
    mesh = random_indexed(rng)
    o, d = random_rays(rng, 5000)
    hits = brdfpy.RayCaster(mesh).closest_hit(o, d)
    h = hits.hit
    tri = triangles(mesh)[hits.triangle[h]]
    u, v = hits.u[h, None].astype(np.float64), hits.v[h, None].astype(np.float64)
    p_bary = (1 - u - v) * tri[:, 0] + u * tri[:, 1] + v * tri[:, 2]
    p_ray = o[h] + hits.t[h, None] * d[h].astype(np.float64)
    np.testing.assert_allclose(p_ray, p_bary, atol=2e-5)
    assert ((hits.u[h] >= 0) & (hits.v[h] >= 0) & (hits.u[h] + hits.v[h] <= 1 + 1e-6)).all()


def test_triangles_are_two_sided_and_t_is_in_units_of_the_direction() -> None:
    rc = brdfpy.RayCaster(brdfpy.plane(2.0, 1))  # y = 0, facing +y
    hits = rc.closest_hit([[0.1, -1, 0.2], [0.1, 1, 0.2]], [[0, 1, 0], [0, -2, 0]])
    np.testing.assert_array_equal(hits.hit, [True, True])  # from behind as from the front
    np.testing.assert_allclose(hits.t, [1.0, 0.5])  # |d| = 2: the plane is half a direction away


def test_scene_geometry_numbers_triangles_through_the_instances() -> None:
    a, b = brdfpy.icosphere(2), brdfpy.torus(16, 8)
    m = np.eye(4)
    m[0, 3] = 3.0
    scene = brdfpy.Scene()
    scene.add(a)
    scene.add(b, transform=m)
    rc = brdfpy.RayCaster(scene)
    assert rc.n_triangles == a.n_faces + b.n_faces
    # Rays down the x axis from far right hit the torus (instance 1) first, its ids offset by a's faces.
    hits = rc.closest_hit([[10, 0.0, 0.0], [10, 0, 0.05]], [-1, 0, 0])
    assert (hits.triangle >= a.n_faces).all()
    alone = brdfpy.RayCaster(b.transformed(m)).closest_hit([[10, 0.0, 0.0], [10, 0, 0.05]], [-1, 0, 0])
    np.testing.assert_array_equal(hits.triangle - a.n_faces, alone.triangle)
    np.testing.assert_array_equal(hits.t, alone.t)
    # The same from a list of (mesh, transform) pairs.
    listed = brdfpy.RayCaster([a, (b, m)]).closest_hit([[10, 0.0, 0.0], [10, 0, 0.05]], [-1, 0, 0])
    np.testing.assert_array_equal(listed.triangle, hits.triangle)


def test_degenerate_triangles_are_skipped_never_hit() -> None:
    v = [[-1, 0, -1], [1, 0, -1], [0, 0, 1], [-1, 0.5, 0], [1, 0.5, 0], [0, 0.5, 0]]  # 2nd: collinear
    m = brdfpy.Mesh(v, [[0, 2, 1], [3, 4, 5]])
    rc = brdfpy.RayCaster(m)
    assert (rc.n_triangles, rc.n_skipped) == (2, 1)
    hits = rc.closest_hit([0.0, 1.0, 0.0], [0, -1, 0])  # through the degenerate one, onto the other
    assert hits.triangle[0] == 0 and np.isclose(hits.t[0], 1.0)


def test_broadcasting_single_origin_and_per_ray_bounds() -> None:
    rc = brdfpy.RayCaster(brdfpy.plane(2.0, 1))
    d = np.array([[0, -1, 0], [0.1, -1, 0], [0, 1, 0]], dtype=np.float32)
    hits = rc.closest_hit([0, 1, 0], d, t_max=[2.0, 0.5, 2.0])
    np.testing.assert_array_equal(hits.hit, [True, False, False])  # too short; pointing away
    assert rc.any_hit([0, 1, 0], [0, -1, 0], t_min=1.5).tolist() == [False]
    assert rc.any_hit([0, 1, 0], [0, -1, 0], t_min=-5.0).tolist() == [True]  # negative t_min acts as 0
    assert rc.any_hit([0, -1, 0], [0, 1, 0]).tolist() == [True]  # two-sided


def test_stats_bounds_and_repr() -> None:
    rc = brdfpy.RayCaster(brdfpy.icosphere(4))
    s = rc.stats()
    assert s["leaves"] > 100 and s["max_depth"] >= 3 and s["max_leaf"] <= 8 and s["sah_cost"] > 0
    lo, hi = rc.bounds()
    np.testing.assert_allclose(lo, -1, atol=1e-3)
    np.testing.assert_allclose(hi, 1, atol=1e-3)
    assert rc.build_seconds >= 0
    assert "5120 triangles" in repr(rc)


def test_results_are_bit_identical_at_any_thread_count(restore_threads: None) -> None:
    rng = np.random.default_rng(9)
    mesh = random_indexed(rng)
    o, d = random_rays(rng, 50_000)  # more than one coherent (Morton-sorted) batch
    out = []
    for n in (1, 2, 4):
        brdfpy.set_num_threads(n)
        rc = brdfpy.RayCaster(mesh)
        out.append((rc.closest_hit(o, d), rc.any_hit(o, d), rc.stats()))
    for h, a, s in out[1:]:
        for x, y in zip(h, out[0][0]):
            np.testing.assert_array_equal(x, y)
        np.testing.assert_array_equal(a, out[0][1])
        assert s == out[0][2]  # the same tree


# --------------------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("kwargs", "exc", "word"),
    [
        ({"origins": [[np.nan, 0, 0]]}, ValueError, "origins"),
        ({"origins": [[np.inf, 0, 0]]}, ValueError, "origins"),
        ({"directions": [[0, 0, 0]]}, ValueError, "directions"),
        ({"directions": [[0, np.nan, 1]]}, ValueError, "directions"),
        ({"t_max": np.nan}, ValueError, "t_max"),
        ({"t_min": np.nan}, ValueError, "t_min"),
        ({"t_min": np.inf}, ValueError, "t_min"),
        ({"t_max": [[1.0]]}, ValueError, "t_max"),
        ({"t_max": [1.0, 2.0, 3.0]}, ValueError, "broadcast"),
        ({"origins": np.zeros((2, 3)), "directions": np.ones((3, 3))}, ValueError, "broadcast"),
        ({"origins": np.zeros((2, 2))}, ValueError, "origins"),
        ({"origins": np.zeros((0, 3))}, ValueError, "origins"),
        ({"origins": "abc"}, TypeError, "origins"),
        ({"directions": None}, TypeError, "directions"),
    ],
)
def test_bad_rays_raise_naming_the_argument(kwargs: dict, exc: type[Exception], word: str) -> None:
    rc = brdfpy.RayCaster(brdfpy.plane())
    args = {"origins": [[0, 1, 0], [0, 2, 0]], "directions": [0, -1, 0], **kwargs}
    for query in (rc.closest_hit, rc.any_hit):
        with pytest.raises(exc, match=word):
            query(**args)


@pytest.mark.parametrize(
    ("geometry", "exc"),
    [(42, TypeError), ("mesh.obj", TypeError), ([], ValueError), (brdfpy.Scene(), ValueError)],
)
def test_bad_geometry(geometry: object, exc: type[Exception]) -> None:
    with pytest.raises(exc, match="geometry"):
        brdfpy.RayCaster(geometry)  # type: ignore[arg-type]


def test_bad_transform_and_obscurance_arguments() -> None:
    with pytest.raises(ValueError, match="transform"):
        brdfpy.RayCaster([(brdfpy.plane(), np.full((4, 4), np.nan))])
    rc = brdfpy.RayCaster(brdfpy.plane())
    with pytest.raises(ValueError, match="normals"):
        rc.obscurance([[0, 0, 0]], [[0, 1, 0], [0, 1, 0]])
    with pytest.raises(ValueError, match="tau"):
        rc.obscurance([[0, 0, 0]], [[0, 1, 0]], tau=-1)
    with pytest.raises(ValueError, match="points"):
        rc.obscurance([[np.nan, 0, 0]], [[0, 1, 0]])
