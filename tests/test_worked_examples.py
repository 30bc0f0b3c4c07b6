"""Seed 004's worked examples ("Numerical Example" sections of the Phong model and of the shading
algorithms) and SCENE.md's check values, recomputed from their inputs.

The expected values here are computed in NumPy from the inputs the seed gives (vectors, intensities,
coefficients); no printed figure is copied. Where the seed's printed figure is wrong, the comment says so
and gives the right value. The course formula under test is seed 004 eq. 12.25,
``I = I_e + I_a k_a + I_i (k_d (n.l) + k_s (n.h)^n)``: brdfpy's ``blinn_phong_classic`` ``shade`` is the
bracketed part, ``k_d max(n.l, 0) + k_s max(n.h, 0)^n`` (specular only where n.l > 0).
"""

from __future__ import annotations

import math

import brdfpy
import numpy as np
import pytest

# Seed 004, "Numerical Example": intensities and material constants (shared by both examples).
I_E, I_A, I_I = 2.0, 1.0, 12.0
K_A, K_D, K_S, SHININESS = 0.3, 0.3, 0.6, 3.0


def unit(a: list[float] | np.ndarray) -> np.ndarray:
    a = np.asarray(a, dtype=np.float64)
    return a / np.linalg.norm(a)


def course_phong(n: np.ndarray, l: np.ndarray, v: np.ndarray) -> float:
    """Eq. 12.25 evaluated directly in float64 from unit vectors."""
    h = unit(l + v)
    diffuse = K_D * max(float(n @ l), 0.0)
    specular = K_S * max(float(n @ h), 0.0) ** SHININESS if n @ l > 0 else 0.0
    return I_E + I_A * K_A + I_I * (diffuse + specular)


def brdfpy_intensity(n: np.ndarray, l: np.ndarray, v: np.ndarray) -> float:
    """The same intensity with brdfpy doing the shading (gray: every channel is equal)."""
    m = brdfpy.model("blinn_phong_classic", kd=K_D, ks=K_S, shininess=SHININESS)
    rgb = m.shade(np.asarray(l, np.float32), np.asarray(v, np.float32), np.asarray(n, np.float32))
    assert rgb.shape == (3,) and rgb[0] == rgb[1] == rgb[2]
    return I_E + I_A * K_A + I_I * float(rgb[0])


# ------------------------------------------------------------- the Phong model's numerical example

N_RAW, L_RAW, V_RAW = [0.0, 2.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 1.0]


def test_phong_model_example_from_unnormalised_inputs() -> None:
    """The seed's vectors are not unit length (n = [0, 2, 0]); brdfpy normalises them itself.
    Recomputed: I = 2.3 + 12 (0.3/sqrt2 + 0.6 (sqrt(2/3))^3) = 8.7655 (the seed rounds it to 8.76)."""
    want = course_phong(unit(N_RAW), unit(L_RAW), unit(V_RAW))
    assert want == pytest.approx(2.3 + 12 * (0.3 / math.sqrt(2) + 0.6 * math.sqrt(2 / 3) ** 3), rel=1e-12)
    assert brdfpy_intensity(np.array(N_RAW), np.array(L_RAW), np.array(V_RAW)) == pytest.approx(
        want, rel=1e-6
    )


def test_phong_model_example_with_the_viewer_in_the_mirror_direction() -> None:
    """v = reflect(l): h = n, and the specular term takes its maximum k_s."""
    n, l = unit(N_RAW), unit(L_RAW)
    v = 2 * (n @ l) * n - l
    h = unit(l + v)
    np.testing.assert_allclose(h, n, atol=1e-15)
    want = course_phong(n, l, v)
    assert want == pytest.approx(I_E + I_A * K_A + I_I * (K_D * (n @ l) + K_S), rel=1e-12)
    assert brdfpy_intensity(n, l, v) == pytest.approx(want, rel=1e-6)


def test_angle_between_mirror_and_view_is_not_twice_the_normal_half_angle_here() -> None:
    """The seed claims angle(r, v) = 2 angle(n, h) = 2 arccos(sqrt(2/3)) = 70.5 degrees (it prints 70).
    That identity holds only when l, v and n are coplanar; here v = [0, 1, 1] leaves the plane of l and n,
    and the true angle is exactly 60 degrees (r.v = 1/2). So the Phong (r.v)^n and the Blinn (n.h)^n
    speculars of this example differ: 0.125 vs 0.544."""
    n, l, v = unit(N_RAW), unit(L_RAW), unit(V_RAW)
    r = np.asarray(brdfpy.vectors.reflect(l.astype(np.float32), n.astype(np.float32)), np.float64)
    assert math.degrees(math.acos(float(r @ v))) == pytest.approx(60.0, abs=1e-4)
    h = np.asarray(brdfpy.vectors.halfway(l.astype(np.float32), v.astype(np.float32)), np.float64)
    assert 2 * math.degrees(math.acos(float(n @ h))) == pytest.approx(70.53, abs=1e-2)
    # The Phong-specular course model sees the 60 degrees.
    phong = brdfpy.model("phong_classic", kd=0.0, ks=1.0, shininess=SHININESS)
    assert float(phong.shade(l, v, n)[0]) == pytest.approx(0.5**SHININESS, rel=1e-5)


# ------------------------------------------------------------ the shading algorithms' example

V0, V1, V2 = np.array([2.0, 2.0, 1.0]), np.array([6.0, 2.0, 1.0]), np.array([4.0, 5.0, 1.0])
N0, N1, N2 = np.array([-1.0, -1.0, 1.0]), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 1.0])
S = np.array([4.0, 3.0, 1.0])  # the scanline point; the scanline y = 3 meets edges v0-v2 and v1-v2
LIGHT = VIEW = np.array([0.0, 0.0, 1.0])


def edge_point(p: np.ndarray, q: np.ndarray, y: float) -> tuple[np.ndarray, float]:
    """Where the scanline ``y`` crosses edge p-q, and the parameter t (point = p + t (q - p))."""
    t = (y - p[1]) / (q[1] - p[1])
    return p + t * (q - p), t


def test_constant_shading_uses_the_polygon_normal() -> None:
    """Polygon normal (v1 - v0) x (v2 - v0) = [0, 0, 12]. The seed's I = 2 + 0.3 + 12*0.3*1 = 5.9 drops
    the specular term, although l = v = n makes it maximal; with eq. 12.25 (as its Gouraud and Phong
    parts use) the constant-shading intensity is 2.3 + 12 (0.3 + 0.6) = 13.1."""
    normal = np.cross(V1 - V0, V2 - V0)
    np.testing.assert_array_equal(normal, [0.0, 0.0, 12.0])
    want = course_phong(unit(normal), LIGHT, VIEW)
    assert want == pytest.approx(I_E + I_A * K_A + I_I * (K_D + K_S), rel=1e-12)
    assert brdfpy_intensity(normal, LIGHT, VIEW) == pytest.approx(want, rel=1e-6)


def test_gouraud_shading_interpolates_vertex_intensities() -> None:
    """Vertex intensities (seed: 5.76, 2.3, 7.39) come out right; the final value does not: the seed
    interpolates its rounded I_a = 6.3, I_b = 4.0 with weights 1.33/2.67 and prints 5.13. s is the
    midpoint of a and b, so I_s = (I_a + I_b)/2 = 5.1518."""
    iv = [brdfpy_intensity(n, LIGHT, VIEW) for n in (N0, N1, N2)]
    for got, n in zip(iv, (N0, N1, N2)):
        assert got == pytest.approx(course_phong(unit(n), LIGHT, VIEW), rel=1e-6)
    a, ta = edge_point(V0, V2, S[1])
    b, tb = edge_point(V1, V2, S[1])
    i_a = (1 - ta) * iv[0] + ta * iv[2]
    i_b = (1 - tb) * iv[1] + tb * iv[2]
    u = (S[0] - a[0]) / (b[0] - a[0])
    assert ta == pytest.approx(1 / 3) and tb == pytest.approx(1 / 3) and u == pytest.approx(0.5)
    i_s = (1 - u) * i_a + u * i_b
    exact = [course_phong(unit(n), LIGHT, VIEW) for n in (N0, N1, N2)]
    want = 0.5 * ((2 * exact[0] + exact[2]) / 3 + (2 * exact[1] + exact[2]) / 3)
    assert i_s == pytest.approx(want, rel=1e-6)


def test_phong_shading_interpolates_normals() -> None:
    """Normals are interpolated linearly from the unit vertex normals, then renormalised.
    The seed's intermediate normals are wrong: n_a = (2 n0 + n2)/3 = [-0.385, -0.149, 0.621] (the seed
    prints +0.15), n_b = (2 n1 + n2)/3 = [0.667, 0.236, 0.236] (the seed prints [0.67, 0.71, 0.71], the
    last two not divided by 3), hence unit n_s = [0.311, 0.096, 0.946] (seed: [0.02, 0.49, 0.87]) and
    I_s = 11.79, not the printed 10.25."""
    _, ta = edge_point(V0, V2, S[1])
    _, tb = edge_point(V1, V2, S[1])
    n_a = (1 - ta) * unit(N0) + ta * unit(N2)
    n_b = (1 - tb) * unit(N1) + tb * unit(N2)
    n_s = unit(0.5 * unit(n_a) + 0.5 * unit(n_b))
    # the y component is negative: 2/3 * (-1/sqrt3) + 1/3 * (1/sqrt2) = -0.149
    third3, third2 = 1 / (3 * math.sqrt(3)), 1 / (3 * math.sqrt(2))
    np.testing.assert_allclose(n_a, [-2 * third3, -2 * third3 + third2, 2 * third3 + third2], rtol=1e-12)
    assert n_a[1] < 0
    want = course_phong(n_s, LIGHT, VIEW)
    assert brdfpy_intensity(n_s, LIGHT, VIEW) == pytest.approx(want, rel=1e-6)
    # Phong shading sees the highlight that Gouraud shading misses (the seed's qualitative point holds).
    assert want > brdfpy_intensity(N0, LIGHT, VIEW)


# ----------------------------------------------------------------- SCENE.md's check values


def scene_colour(p: np.ndarray) -> np.ndarray:
    """SCENE.md's shading formula, float64, at a point P = N on the unit sphere, using brdfpy for the
    per-light ``diff + spec`` (blinn_phong_classic) and adding the lights and ambient here."""
    kd, ks, ambient = np.array([0.8, 0.3, 0.2]), np.array([0.5, 0.5, 0.5]), 0.05
    eye = np.array([0.0, 0.0, 3.0])
    n = unit(p)
    v = unit(eye - p)
    model = brdfpy.model("blinn_phong_classic", kd=kd.tolist(), ks=ks.tolist(), shininess=32.0)
    colour = ambient * kd
    light_pos = np.array([2.0, 2.0, 2.0])
    lights = [
        (unit([1.0, 1.0, 1.0]), 1.0),  # directional: L = -d, E = 1
        (unit(light_pos - p), 10.0 / float((light_pos - p) @ (light_pos - p))),  # point: I / d^2
    ]
    for l, e in lights:
        colour = colour + e * model.shade(l.astype(np.float32), v.astype(np.float32), n.astype(np.float32))
    return colour


def scene_colour_numpy(p: np.ndarray) -> np.ndarray:
    """The same formula entirely in NumPy (no brdfpy)."""
    kd, ks, ambient = np.array([0.8, 0.3, 0.2]), np.array([0.5, 0.5, 0.5]), 0.05
    n = unit(p)
    v = unit(np.array([0.0, 0.0, 3.0]) - p)
    c = ambient * kd
    light_pos = np.array([2.0, 2.0, 2.0])
    for l, e in [
        (unit([1.0, 1.0, 1.0]), 1.0),
        (unit(light_pos - p), 10.0 / float((light_pos - p) @ (light_pos - p))),
    ]:
        h = unit(l + v)
        spec = ks * max(float(n @ h), 0.0) ** 32 if n @ l > 0 else 0.0 * ks
        c = c + e * (kd * max(float(n @ l), 0.0) + spec)
    return c


@pytest.mark.parametrize("p", [[0.0, 0.0, 1.0], [0.5, 0.5, 0.707107], [-0.6, -0.6, 0.529150]])
def test_scene_check_points(p: list[float]) -> None:
    point = np.array(p)
    np.testing.assert_allclose(scene_colour(point), scene_colour_numpy(point), rtol=1e-5)
