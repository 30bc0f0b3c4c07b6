"""brdfpy.Mesh from Python: construction, vertex normals by seed 004's three weightings and Newell's
normal on the seed's quad (recomputed here), procedural meshes against SCENE.md's definitions, and
loading OBJ / PLY files (ASCII and binary) and foreign mesh objects."""

from __future__ import annotations

import struct
from pathlib import Path
from types import SimpleNamespace

import brdfpy
import numpy as np
import pytest

from raster_oracle import geometry as og

# Seed 004 "Numerical Example" of "The Normal Vector": a slightly non-planar quad.
QUAD = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.5]])


def unit(a: np.ndarray) -> np.ndarray:
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def test_newell_normal_of_the_seed_quad() -> None:
    # a = sum (y_i - y_i+1)(z_i + z_i+1), b = sum (z_i - z_i+1)(x_i + x_i+1),
    # c = sum (x_i - x_i+1)(y_i + y_i+1)
    x, y, z = QUAD.T
    xn, yn, zn = np.roll(QUAD, -1, axis=0).T
    abc = [np.sum((y - yn) * (z + zn)), np.sum((z - zn) * (x + xn)), np.sum((x - xn) * (y + yn))]
    np.testing.assert_allclose(abc, [0.5, -0.5, 2.0])  # as the seed prints
    np.testing.assert_allclose(og.newell(QUAD), abc)


def test_corner_normal_average_of_the_seed_quad() -> None:
    # Seed 004 method 1: n_vi = (v_i+1 - v_i) x (v_i-1 - v_i). At v4 that is (0, -1, -0.5) x (1, 0, -0.5)
    # = (0.5, -0.5, 1); the seed prints (0.25, -0.5, 1) (a slip), and so its average (0.18, -0.23, 0.96).
    corners = [np.cross(QUAD[(i + 1) % 4] - QUAD[i], QUAD[i - 1] - QUAD[i]) for i in range(4)]
    np.testing.assert_allclose(corners, [[0, -0.5, 1], [0, 0, 1], [0.5, 0, 1], [0.5, -0.5, 1]])
    avg = unit(np.mean(unit(np.array(corners)), axis=0))
    np.testing.assert_allclose(og.corner_average(QUAD), avg)
    np.testing.assert_allclose(avg, [0.2250, -0.2250, 0.9480], atol=1e-4)


@pytest.mark.parametrize("faces", [[[0, 1, 2], [0, 2, 3]], [[1, 2, 3], [1, 3, 0]]], ids=["diag02", "diag13"])
def test_vertex_normal_weightings_on_the_seed_quad(faces: list[list[int]]) -> None:
    f = np.array(faces)
    cross = np.cross(QUAD[f[:, 1]] - QUAD[f[:, 0]], QUAD[f[:, 2]] - QUAD[f[:, 0]])
    fhat = unit(cross)

    def angle(face: np.ndarray, vertex: int) -> float:
        k = list(face).index(vertex)
        a, b, c = QUAD[face[k]], QUAD[face[(k + 1) % 3]], QUAD[face[(k + 2) % 3]]
        return float(np.arccos(unit(b - a) @ unit(c - a)))

    want = {}
    for w in ("equal", "area", "angle"):
        rows = []
        for vtx in range(4):
            acc = np.zeros(3)
            for i, face in enumerate(f):
                if vtx in face:
                    acc += {"equal": fhat[i], "area": cross[i], "angle": angle(face, vtx) * fhat[i]}[w]
            rows.append(unit(acc))
        want[w] = np.array(rows)
        got = brdfpy.Mesh(QUAD, f).compute_normals(w).normals
        np.testing.assert_allclose(got, want[w], atol=2e-6, err_msg=w)
        np.testing.assert_allclose(og.vertex_normals(QUAD, f, w), want[w], atol=1e-12, err_msg=w)
    apex = f[0, 0]
    if apex == 0:
        # split along v1-v3 the weightings differ at the shared vertices (split along v2-v4 the two
        # triangles are mirror images: equal areas and angles, so all three weightings coincide)
        assert not np.allclose(want["equal"][apex], want["area"][apex], atol=1e-3)
        assert not np.allclose(want["angle"][apex], want["area"][apex], atol=1e-3)
    # area weighting at a vertex of both triangles of a fan = Newell's normal of the quad: the fan's
    # cross products sum to twice the polygon's vector area, which Newell's formula computes
    np.testing.assert_allclose(want["area"][apex], unit(og.newell(QUAD)), atol=1e-12)
    # default normals are angle-weighted
    np.testing.assert_allclose(brdfpy.Mesh(QUAD, f).normals, want["angle"], atol=2e-6)


def test_face_normals_are_unit_cross_products() -> None:
    v, f = og.icosphere(1)
    m = brdfpy.Mesh(v, f)
    np.testing.assert_allclose(m.face_normals(), unit(og.face_cross(v, f)), atol=2e-6)


def test_given_normals_are_normalised_and_kept() -> None:
    n = np.array([[0, 0, 2.0], [0, 3.0, 0], [1, 1, 1]])
    m = brdfpy.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], normals=n)
    np.testing.assert_allclose(m.normals, unit(n), atol=1e-6)
    assert m.vertices.dtype == np.float32 and m.faces.dtype == np.uint32


# ------------------------------------------------------------------------------------ procedural


def test_icosphere_follows_scene_md_subdivision() -> None:
    base = brdfpy.icosphere(0)
    v0, f0 = np.asarray(base.vertices, float), np.asarray(base.faces, np.int64)
    assert len(v0) == 12 and len(f0) == 20
    np.testing.assert_allclose(np.linalg.norm(v0, axis=1), 1, atol=1e-6)
    for level in (1, 2, 3):
        m = brdfpy.icosphere(level)
        v, f = og.icosphere(level, base=(v0, f0))
        # vertex order (edge-key order of the new midpoints) and face order (4 children per face)
        np.testing.assert_array_equal(m.faces, f)
        np.testing.assert_allclose(m.vertices, v, atol=2e-6)
        np.testing.assert_allclose(m.normals, m.vertices, atol=2e-6)  # normals = positions
    m = brdfpy.icosphere(3)
    v, f = np.asarray(m.vertices, float), np.asarray(m.faces)
    assert np.all(np.sum(og.face_cross(v, f) * v[f].mean(axis=1), axis=1) > 0), "faces must be CCW outward"


@pytest.mark.parametrize(("big", "small"), [(16, 8), (7, 3)])
def test_torus_geometry(big: int, small: int) -> None:
    m = brdfpy.torus(big, small)
    v, f, n = (np.asarray(a, float) for a in (m.vertices, m.faces, m.normals))
    assert len(f) == 2 * big * small
    ring = np.hypot(v[:, 0], v[:, 1])
    np.testing.assert_allclose((ring - 0.7) ** 2 + v[:, 2] ** 2, 0.09, atol=1e-6)  # R 0.7, r 0.3, axis +z
    centre = np.column_stack([0.7 * v[:, 0] / ring, 0.7 * v[:, 1] / ring, np.zeros(len(v))])
    np.testing.assert_allclose(n, unit(v - centre), atol=1e-5)  # exact normals
    fc = og.face_cross(v, f.astype(int))
    mid = v[f.astype(int)].mean(axis=1)
    r = np.hypot(mid[:, 0], mid[:, 1])
    tube = mid - np.column_stack([0.7 * mid[:, 0] / r, 0.7 * mid[:, 1] / r, np.zeros(len(mid))])
    assert np.all(np.sum(fc * tube, axis=1) > 0), "faces must be CCW outward"
    assert m.stats()["watertight"]


def test_plane_faces_up() -> None:
    m = brdfpy.plane(3.0, 4)
    v = np.asarray(m.vertices)
    assert len(m.faces) == 2 * 16
    np.testing.assert_allclose(v[:, 1], 0)
    np.testing.assert_allclose([v[:, 0].min(), v[:, 0].max()], [-1.5, 1.5], atol=1e-6)
    assert np.all(m.face_normals()[:, 1] > 0.999)


# ----------------------------------------------------------------------------------------- files


TRI_V = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
TRI_F = np.array([[0, 1, 2], [0, 2, 3]])


def test_obj_with_quads_normals_and_comments(tmp_path: Path) -> None:
    p = tmp_path / "quad.obj"
    p.write_text(
        "# a unit square as one quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n"
    )
    m = brdfpy.load_mesh(p)
    assert m.n_faces == 2
    tris = {tuple(sorted(map(tuple, np.asarray(m.vertices)[t].tolist()))) for t in np.asarray(m.faces)}
    assert tris == {tuple(sorted(map(tuple, TRI_V[t].tolist()))) for t in TRI_F}
    np.testing.assert_allclose(m.normals, np.tile([0, 0, 1], (m.n_vertices, 1)), atol=1e-6)


def ply_header(fmt: str, nv: int, nf: int, extra: str = "") -> bytes:
    return (
        f"ply\nformat {fmt} 1.0\ncomment made by tests\nelement vertex {nv}\n"
        f"property float x\nproperty float y\nproperty float z\n{extra}"
        f"element face {nf}\nproperty list uchar int vertex_indices\nend_header\n"
    ).encode()


def test_ply_ascii_with_extra_property(tmp_path: Path) -> None:
    p = tmp_path / "sq.ply"
    body = "".join(f"{x} {y} {z} 0.5\n" for x, y, z in TRI_V) + "".join(
        f"3 {a} {b} {c}\n" for a, b, c in TRI_F
    )
    p.write_bytes(ply_header("ascii", 4, 2, "property float confidence\n") + body.encode())
    m = brdfpy.load_mesh(p)
    np.testing.assert_allclose(m.vertices, TRI_V)
    np.testing.assert_array_equal(m.faces, TRI_F)


@pytest.mark.parametrize(("fmt", "endian"), [("binary_little_endian", "<"), ("binary_big_endian", ">")])
def test_ply_binary(tmp_path: Path, fmt: str, endian: str) -> None:
    p = tmp_path / "sq.ply"
    body = b"".join(struct.pack(endian + "3f", *row) for row in TRI_V)
    body += b"".join(struct.pack(endian + "B3i", 3, *t) for t in TRI_F)
    p.write_bytes(ply_header(fmt, 4, 2) + body)
    m = brdfpy.load_mesh(p)
    np.testing.assert_allclose(m.vertices, TRI_V)
    np.testing.assert_array_equal(m.faces, TRI_F)


def test_from_any_takes_vertices_faces_and_normals() -> None:
    v, f = og.icosphere(1)
    obj = SimpleNamespace(vertices=v, faces=f, vertex_normals=-v)
    m = brdfpy.Mesh.from_any(obj)
    np.testing.assert_allclose(m.vertices, v, atol=1e-6)
    np.testing.assert_array_equal(m.faces, f)
    np.testing.assert_allclose(m.normals, -v, atol=1e-6)
    m2 = brdfpy.Mesh.from_any(SimpleNamespace(vertices=v, triangles=f))
    np.testing.assert_allclose(m2.normals, og.vertex_normals(v, f, "angle"), atol=2e-6)
    assert brdfpy.Mesh.from_any(m) is m
    with pytest.raises(TypeError, match="vertices"):
        brdfpy.Mesh.from_any(SimpleNamespace(points=v))


def test_meshes_are_usable_from_scenes_with_a_transform() -> None:
    # mesh.transformed: positions by M, normals by the inverse transpose
    m = brdfpy.icosphere(1)
    xf = og.translation((1, 2, 3)) @ og.scaling((2.0, 1.0, 0.5))
    t = m.transformed(xf)
    v = np.asarray(m.vertices, float)
    np.testing.assert_allclose(t.vertices, v * [2, 1, 0.5] + [1, 2, 3], atol=1e-5)
    np.testing.assert_allclose(t.normals, unit(np.asarray(m.normals, float) / [2, 1, 0.5]), atol=1e-5)


def test_a_scene_keeps_the_mesh_as_it_was_when_added() -> None:
    # documented in brdfpy.Mesh: "A scene holds the mesh as it was when added: later compute_normals or
    # flip_winding calls do not change scenes it was already added to"
    mesh = brdfpy.icosphere(2)
    scene = brdfpy.Scene()
    scene.add(mesh, "lambert")
    scene.add_light(brdfpy.DirectionalLight((0, 0, -1)))
    cam = brdfpy.Camera.perspective((0, 0, 3))
    before = np.array(scene.render(cam, 32, 24, outputs="all").hdr)
    mesh.flip_winding().compute_normals("equal")
    after = np.array(scene.render(cam, 32, 24, outputs="all").hdr)
    np.testing.assert_array_equal(before, after)
    assert (before > 0).any()
