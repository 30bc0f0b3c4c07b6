"""Seed 004's numerical examples of the shading algorithms, rendered by brdfpy and read at the point s.

The triangle (seed 004, "Numerical Example" after "Quadratic Interpolation of Vertex Normals (4)"):
``v0 = (2, 2, 1)``, ``v1 = (6, 2, 1)``, ``v2 = (4, 5, 1)`` with vertex normals ``(-1, -1, 1)``,
``(1, 0, 0)``, ``(0, 1, 1)``; the scanline y = 3 meets the edges at ``a = (8/3, 3, 1)`` and
``b = (16/3, 3, 1)`` and ``s = (4, 3, 1)`` is its midpoint -- which is also the triangle's centroid
(barycentrics 1/3 each). Light and viewer at infinity on +z (``l = v = (0, 0, 1)``), ``Ie = 2``,
``Ia = 1``, ``Ii = 12``, ``ka = 0.3``, ``kd = 0.3``, ``ks = 0.6``, ``n = 3``, and the Phong model of
eq. 12.25 with the halfway vector (``blinn_phong_classic``).

The render: an orthographic camera straight down -z (the viewer at infinity, so v = +z at every
point), centred on s with an odd image size so that the centre pixel samples s exactly; a directional
light travelling along -z with color 12. Every expected value below is recomputed here from those
data; the seed's printed figures are not used (where they are off, a comment says so).
"""

from __future__ import annotations

import brdfpy
import numpy as np
import pytest

V = np.array([[2.0, 2.0, 1.0], [6.0, 2.0, 1.0], [4.0, 5.0, 1.0]])
N = np.array([[-1.0, -1.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 1.0]])
S = np.array([4.0, 3.0, 1.0])
L = VIEW = np.array([0.0, 0.0, 1.0])
IE, IA, II = 2.0, 1.0, 12.0
KA, KD, KS, SHININESS = 0.3, 0.3, 0.6, 3.0
SIZE = 65  # odd: the centre pixel's centre is the image centre
#: float32 rendering of values ~10 with a cube: well within 1e-4 relative (the pixel samples s exactly:
#: every vertex lands on a multiple of 1/256 px, so vertex snapping changes nothing).
RTOL = 1e-4


def unit(a: np.ndarray) -> np.ndarray:
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def phong_model(n: np.ndarray, ks: float = KS) -> float:
    """Seed 004 eq. 12.25 with light and view at infinity on +z: ``h = l = v``; the specular term is
    dropped where n.l <= 0 (SCENE.md's gate: a surface facing away from the light gets no highlight)."""
    n = unit(n)
    nl = float(n @ L)
    h = unit(L + VIEW)
    spec = ks * max(float(n @ h), 0.0) ** SHININESS if nl > 0 else 0.0
    return IE + IA * KA + II * (KD * max(nl, 0.0) + spec)


def render_s(shading: str, ks: float = KS, normals: np.ndarray = N) -> np.ndarray:
    scene = brdfpy.Scene(ambient_light=IA)
    mesh = brdfpy.Mesh(V, [[0, 1, 2]], normals=normals)
    material = brdfpy.model("blinn_phong_classic", kd=KD, ks=ks, shininess=SHININESS)
    scene.add(mesh, material, ambient=KA, emission=IE)
    scene.add_light(brdfpy.DirectionalLight(direction=-L, color=II))
    cam = brdfpy.Camera.orthographic(eye=S + np.array([0.0, 0.0, 10.0]), target=S, up=(0, 1, 0), height=8.0)
    img = scene.render(cam, SIZE, SIZE, shading=shading, outputs="all")
    c = SIZE // 2
    assert img.triangle_id[c, c] == 0
    return np.asarray(img.hdr[c, c], dtype=np.float64)


def test_the_point_s_is_the_scanline_midpoint_and_the_centroid() -> None:
    a = V[0] + (V[2] - V[0]) / 3  # y = 3 on edge v0-v2
    b = V[1] + (V[2] - V[1]) / 3  # y = 3 on edge v1-v2
    np.testing.assert_allclose(a, [8 / 3, 3, 1])  # the seed prints 2.66
    np.testing.assert_allclose(b, [16 / 3, 3, 1])  # the seed prints 5.33
    np.testing.assert_allclose((a + b) / 2, S)
    np.testing.assert_allclose(V.mean(axis=0), S)


def test_constant_shading_with_the_seeds_diffuse_only_model() -> None:
    # The seed's constant shading has no specular term: I = Ie + Ia ka + Ii kd n_z with the face normal
    # (v1 - v0) x (v2 - v0) = (0, 0, 12): 2 + 0.3 + 12 * 0.3 = 5.9. Here: the same model with ks = 0.
    face = np.cross(V[1] - V[0], V[2] - V[0])
    np.testing.assert_allclose(face, [0, 0, 12])
    want = IE + IA * KA + II * KD * unit(face)[2]
    assert want == pytest.approx(5.9)
    np.testing.assert_allclose(render_s("flat", ks=0.0), [want] * 3, rtol=RTOL)


def test_flat_shading_applies_the_whole_model_to_the_face_normal() -> None:
    # brdfpy's flat mode evaluates the material (here with its specular) once per triangle with the face
    # normal: at n = l = v = +z, 2.3 + 12 (0.3 + 0.6) = 13.1.
    want = phong_model(np.cross(V[1] - V[0], V[2] - V[0]))
    assert want == pytest.approx(13.1)
    np.testing.assert_allclose(render_s("flat"), [want] * 3, rtol=RTOL)


def gouraud_at_s() -> float:
    iv = [phong_model(n) for n in N]
    # the vertex intensities (the seed prints 5.76, 2.3, 7.39, which these round to)
    by_hand = [2.3 + 12 * (0.3 + 0.2) / 3**0.5, 2.3, 2.3 + 12 * 0.6 / 2**0.5]
    np.testing.assert_allclose(iv, by_hand, rtol=1e-12)
    # the seed's route: along the edges to a and b (a third of the way to v2), then halfway along ab
    ia = (iv[2] + 2 * iv[0]) / 3
    ib = (iv[2] + 2 * iv[1]) / 3
    i_s = (ia + ib) / 2
    # = the barycentric interpolation at the centroid (the view is affine, so they coincide)
    assert i_s == pytest.approx(np.mean(iv), rel=1e-12)
    # 5.152; the seed prints I_s = 5.13, from 1.33/2.67 rounded weights instead of exactly 1/2
    # (its I_a = 6.3 and I_b = 4.0 are right).
    return i_s


def test_gouraud_shading_at_s() -> None:
    want = gouraud_at_s()
    assert want == pytest.approx(5.152, abs=1e-3)
    np.testing.assert_allclose(render_s("gouraud"), [want] * 3, rtol=RTOL)


def phong_normal_at_s() -> np.ndarray:
    nh = unit(N)
    # the seed's route: unit vertex normals interpolated to a and b, normalised, then to s
    na = (nh[2] + 2 * nh[0]) / 3  # (-0.385, -0.149, 0.621): the seed prints +0.15 for y (a sign slip)
    nb = (nh[2] + 2 * nh[1]) / 3  # (0.667, 0.236, 0.236): the seed prints (0.67, 0.71, 0.71), y and z
    # not divided by 3
    ns_scan = unit((unit(na) + unit(nb)) / 2)
    # a renderer's route: barycentric interpolation of the unit vertex normals at s, normalised. The
    # two agree here only because |n_a| = |n_b| (= sqrt(5)/3) for this triangle.
    assert np.linalg.norm(na) == pytest.approx(np.linalg.norm(nb))
    ns = unit(nh.mean(axis=0))
    np.testing.assert_allclose(ns_scan, ns, atol=1e-12)
    return ns  # (0.311, 0.0955, 0.946); the seed prints (0.02, 0.49, 0.87)


def test_phong_shading_at_s() -> None:
    ns = phong_normal_at_s()
    want = phong_model(ns)
    # 11.79; the seed prints 10.25, carried over from its wrong n_b. Its conclusion stands: Phong shading
    # shows the highlight at s that constant (5.9 diffuse-only) and Gouraud (5.15) shading miss.
    assert want == pytest.approx(11.79, abs=0.01)
    assert want > gouraud_at_s() and want > 5.9
    np.testing.assert_allclose(render_s("phong"), [want] * 3, rtol=RTOL)


def test_quadratic_normal_interpolation_at_s() -> None:
    # van Overveld & Wyvill as seed 004 gives it per edge: n(t) = n0 + t a + t^2 b with
    # b = 3 ((n0 + n1).d / d.d) d, a = n1 - n0 - b, d = p1 - p0; over the triangle, the quadratic in the
    # barycentrics that is this on every edge: sum b_i^2 n_i + sum_{i<j} b_i b_j n_ij, n_ij = n_i + n_j - b_ij
    # (Bernstein form of the edge formula). At the centroid: (sum n_i + sum n_ij)/9.
    nh = unit(N)
    total = nh.sum(axis=0)
    for i, j in ((0, 1), (1, 2), (2, 0)):
        d = V[j] - V[i]
        b = 3 * ((nh[i] + nh[j]) @ d) / (d @ d) * d
        total = total + (nh[i] + nh[j] - b)
    ns = unit(total / 9)
    # the seed's edges lie in the plane z = 1 and all corrections b lie in it: only x and y change
    assert not np.allclose(ns, phong_normal_at_s(), atol=1e-3)
    want = phong_model(ns)
    np.testing.assert_allclose(render_s("quadratic"), [want] * 3, rtol=RTOL)


def test_shading_modes_agree_where_the_normals_are_all_the_face_normal() -> None:
    # with every vertex normal = the face normal, all four algorithms must give the same value at s
    flat_normals = np.tile([0.0, 0.0, 1.0], (3, 1))
    want = phong_model(np.array([0.0, 0.0, 1.0]))
    for mode in ("flat", "gouraud", "phong", "quadratic"):
        np.testing.assert_allclose(render_s(mode, normals=flat_normals), [want] * 3, rtol=RTOL, err_msg=mode)
