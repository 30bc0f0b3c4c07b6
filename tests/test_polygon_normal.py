"""Polygon normals (SPEC row 16, seed 004 "Normals"): Newell's method, the cross product, corner average."""

from __future__ import annotations

import brdfpy
import numpy as np
import pytest


def _fan_area_vector(p: np.ndarray) -> np.ndarray:
    """Twice the vector area of a polygon as the sum of its fan triangles' cross products (independent)."""
    return sum(np.cross(p[i] - p[0], p[i + 1] - p[0]) for i in range(1, len(p) - 1))


def test_newell_is_twice_the_vector_area_of_a_planar_polygon_in_any_orientation() -> None:
    rng = np.random.default_rng(7)
    for _ in range(20):
        # A convex pentagon in a random plane, far from the origin.
        ang = np.sort(rng.uniform(0, 2 * np.pi, 5))
        flat = np.stack([np.cos(ang), np.sin(ang), np.zeros(5)], axis=1) * rng.uniform(0.5, 3)
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        pts = flat @ q.T + rng.normal(size=3) * 100
        want = _fan_area_vector(pts)
        np.testing.assert_allclose(brdfpy.polygon_normal(pts, "newell"), want, rtol=2e-3, atol=2e-3)


def test_cross_is_the_first_corner_triangle_normal() -> None:
    pts = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 1], [0, 1, 0]], dtype=float)
    np.testing.assert_allclose(
        brdfpy.polygon_normal(pts, "cross"), np.cross(pts[1] - pts[0], pts[2] - pts[0])
    )


def test_corner_average_of_a_planar_convex_polygon_is_its_unit_normal() -> None:
    pts = np.array([[0, 0, 0], [1, 0, 0], [1.5, 1, 0], [0.5, 1.8, 0], [-0.3, 1, 0]], dtype=float)
    np.testing.assert_allclose(brdfpy.polygon_normal(pts, "corner_average"), [0, 0, 1], atol=1e-6)


def test_non_planar_quad_newell_lies_between_its_two_triangle_normals() -> None:
    # A twisted quad: Newell's normal is the sum of the two fan triangles' normals.
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.4], [0, 1, 0]], dtype=float)
    want = np.cross(pts[1] - pts[0], pts[2] - pts[0]) + np.cross(pts[2] - pts[0], pts[3] - pts[0])
    np.testing.assert_allclose(brdfpy.polygon_normal(pts, "newell"), want, atol=1e-6)


@pytest.mark.parametrize("size", [1e-30, 1e-20, 1.0, 1e20, 1e37])
def test_corner_average_is_the_unit_normal_at_any_scale(size: float) -> None:
    # Unit corner normals do not depend on the polygon's size: no overflow or underflow to 0 at the extremes.
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float64) * size + [0, 0, size]
    np.testing.assert_allclose(brdfpy.polygon_normal(pts, "corner_average"), [0, 0, 1], atol=1e-6)


@pytest.mark.parametrize(
    ("points", "method", "match"),
    [
        ([[0, 0, 0], [1, 0, 0]], "newell", "points"),
        ([[0, 0], [1, 0], [0, 1]], "newell", "points"),
        ([[0, 0, 0], [1, 0, 0], [0, np.nan, 0]], "newell", "points"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], "bogus", "method"),
        # Finite vertices whose unnormalised normal (twice an area) is beyond float32: refused, not inf.
        ([[0, 0, 0], [3e19, 0, 0], [0, 3e19, 0]], "cross", "points: .*overflows"),
        ([[0, 0, 0], [3e19, 0, 0], [0, 3e19, 0]], "newell", "points: .*overflows"),
    ],
)
def test_bad_polygons_are_refused_naming_the_argument(
    points: list[list[float]], method: str, match: str
) -> None:
    with pytest.raises(ValueError, match=match):
        brdfpy.polygon_normal(points, method)
