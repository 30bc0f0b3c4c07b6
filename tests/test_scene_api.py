"""The Python scene API: meshes in and out, cameras, lights, Scene.render and the Image it returns, the GIL
release, and the error contract (bad input -> ValueError/TypeError naming the argument)."""

from __future__ import annotations

import io
import threading
import types

import brdfpy
import numpy as np
import pytest
from PIL import Image as PILImage

KD = (0.8, 0.3, 0.2)

TRI_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64)
TRI_F = np.array([[0, 1, 2]])


def canonical(level: int = 3) -> tuple[brdfpy.Scene, brdfpy.Camera]:
    """SCENE.md's scene (classic Blinn-Phong, ambient 0.05 kd, directional + inverse-square point light)."""
    scene = brdfpy.Scene()
    model = brdfpy.model("blinn_phong_classic", kd=KD, ks=0.5, shininess=32)
    scene.add(brdfpy.icosphere(level), model, ambient=tuple(0.05 * c for c in KD))
    scene.add_light(brdfpy.DirectionalLight((-1, -1, -1), 1.0))
    scene.add_light(brdfpy.PointLight((2, 2, 2), 10.0))
    return scene, brdfpy.Camera.perspective((0, 0, 3), (0, 0, 0), fovy=45)


# -- meshes ----------------------------------------------------------------------------------------------


def test_mesh_from_numpy_round_trips_and_computes_unit_normals_on_the_front_side():
    m = brdfpy.Mesh(TRI_V, TRI_F)
    assert m.vertices.dtype == np.float32 and m.faces.dtype == np.uint32
    np.testing.assert_array_equal(m.vertices, TRI_V.astype(np.float32))
    np.testing.assert_array_equal(m.faces, TRI_F)
    # Counter-clockwise seen from +z: the normal points to +z.
    np.testing.assert_allclose(m.normals, np.tile([0, 0, 1], (3, 1)), atol=1e-7)
    assert len(m) == 1 and m.n_vertices == 3 and not m.vertices.flags.writeable


def test_given_normals_are_normalised_and_kept():
    n = np.array([[0, 0, 2.0], [0, 3.0, 0], [1, 1, 0]])
    m = brdfpy.Mesh(TRI_V, TRI_F, n)
    np.testing.assert_allclose(m.normals, n / np.linalg.norm(n, axis=1, keepdims=True), rtol=1e-6)


def test_compute_normals_weights_face_normals_by_one_area_or_corner_angle():
    # Vertex 0 is shared by three faces of different areas, angles and orientations (seed 004 eqs. 12.31-33).
    v = np.array([[0, 0, 0], [4, 0, 0], [0, 4, 0], [-1, 0.5, 1], [0.3, -1, 1]], dtype=float)
    f = np.array([[0, 1, 2], [0, 2, 3], [0, 4, 1]])
    m = brdfpy.Mesh(v, f)
    cross = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    unit = cross / np.linalg.norm(cross, axis=1, keepdims=True)
    e1, e2 = v[f[:, 1]] - v[0], v[f[:, 2]] - v[0]
    angle = np.arccos((e1 * e2).sum(1) / np.linalg.norm(e1, axis=1) / np.linalg.norm(e2, axis=1))
    expect = {
        "equal": unit.sum(0),
        "area": cross.sum(0),
        "angle": (angle[:, None] * unit).sum(0),
    }
    got = {}
    for w, e in expect.items():
        got[w] = m.compute_normals(w).normals[0].copy()
        np.testing.assert_allclose(got[w], e / np.linalg.norm(e), atol=1e-6, err_msg=w)
    assert (
        min(
            np.linalg.norm(got[a] - got[b])
            for a, b in [("equal", "area"), ("equal", "angle"), ("area", "angle")]
        )
        > 1e-3
    )
    with pytest.raises(ValueError, match="weighting"):
        m.compute_normals("median")


def test_from_any_takes_anything_with_vertices_and_faces_without_importing_its_library():
    src = types.SimpleNamespace(vertices=TRI_V.tolist(), faces=TRI_F.tolist())
    m = brdfpy.Mesh.from_any(src)
    np.testing.assert_array_equal(m.faces, TRI_F)
    # trimesh-like: vertex_normals are used; Open3D-like: .triangles instead of .faces.
    tm = types.SimpleNamespace(vertices=TRI_V, faces=TRI_F, vertex_normals=np.tile([0, 0, -1.0], (3, 1)))
    np.testing.assert_allclose(brdfpy.Mesh.from_any(tm).normals[:, 2], -1)
    o3d = types.SimpleNamespace(vertices=TRI_V, triangles=TRI_F)
    assert brdfpy.Mesh.from_any(o3d).n_faces == 1
    assert brdfpy.Mesh.from_any(m) is m
    with pytest.raises(TypeError, match="obj"):
        brdfpy.Mesh.from_any(object())


def test_procedural_meshes_have_the_documented_counts_and_shapes():
    ico = brdfpy.icosphere(2)
    assert (ico.n_faces, ico.n_vertices) == (20 * 16, 10 * 16 + 2)
    np.testing.assert_allclose(np.linalg.norm(ico.vertices, axis=1), 1, atol=1e-6)
    np.testing.assert_allclose(ico.normals, ico.vertices, atol=1e-6)
    tor = brdfpy.torus(12, 8)
    assert tor.n_faces == 2 * 12 * 8
    r = np.linalg.norm(tor.vertices[:, :2], axis=1)
    assert r.min() == pytest.approx(0.4, abs=1e-5) and r.max() == pytest.approx(1.0, abs=1e-5)
    pl = brdfpy.plane(2.0, 3)
    assert pl.n_faces == 18 and np.allclose(pl.normals, [0, 1, 0])
    assert brdfpy.cube(1.0, 1).stats()["signed_volume"] == pytest.approx(1.0)
    for name in brdfpy.BUILTIN_MESHES:
        m = brdfpy.builtin_mesh(name)
        assert m.n_faces > 1000 and m.stats()["signed_volume"] > 0


def test_load_mesh_reads_obj_and_ply_files_and_refuses_malformed_ones(tmp_path):
    obj = tmp_path / "quad.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
    m = brdfpy.load_mesh(obj)
    assert m.n_faces == 2 and m.n_vertices == 4
    ply = tmp_path / "tri.ply"
    ply.write_text(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
    )
    assert brdfpy.load_mesh(str(ply)).n_faces == 1
    bad = tmp_path / "bad.ply"
    bad.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0\n")
    with pytest.raises(ValueError, match=r"bad\.ply"):
        brdfpy.load_mesh(bad)
    with pytest.raises(FileNotFoundError):
        brdfpy.load_mesh(tmp_path / "missing.obj")
    (tmp_path / "x.stl").write_text("solid x\n")
    with pytest.raises(ValueError):
        brdfpy.load_mesh(tmp_path / "x.stl")


@pytest.mark.parametrize(
    ("vertices", "faces", "exc", "word"),
    [
        (np.zeros((0, 3)), TRI_F, ValueError, "vertices"),
        (TRI_V, np.zeros((0, 3), int), ValueError, "faces"),
        (TRI_V, [[0, 1, 3]], ValueError, "faces"),
        (TRI_V, [[0, -1, 2]], ValueError, "faces"),
        ([[0, 0, np.nan], [1, 0, 0], [0, 1, 0]], TRI_F, ValueError, "vertices"),
        ([[0, 0, np.inf], [1, 0, 0], [0, 1, 0]], TRI_F, ValueError, "vertices"),
        (TRI_V[:, :2], TRI_F, ValueError, "vertices"),
        (TRI_V, [[0.0, 1.0, 2.0]], TypeError, "faces"),
        ("abc", TRI_F, TypeError, "vertices"),
    ],
)
def test_bad_meshes_raise_naming_the_argument(vertices, faces, exc, word):
    with pytest.raises(exc, match=word):
        brdfpy.Mesh(vertices, faces)


# -- cameras and lights ----------------------------------------------------------------------------------


def test_camera_matrices_are_scene_md_lookat_and_glu_perspective_with_degrees():
    cam = brdfpy.Camera.perspective((0, 0, 3), (0, 0, 0), fovy=45)
    np.testing.assert_allclose(
        cam.view_matrix(), np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, -3], [0, 0, 0, 1]])
    )
    f = 1 / np.tan(np.radians(22.5))
    p = cam.projection_matrix(16 / 9)
    np.testing.assert_allclose([p[0, 0], p[1, 1], p[3, 2]], [f * 9 / 16, f, -1], rtol=1e-6)
    assert cam.fovy == pytest.approx(45) and cam.kind == "perspective"
    ortho = brdfpy.Camera.orthographic((0, 0, 5), height=4)
    assert ortho.height == 4 and ortho.fovy is None


@pytest.mark.parametrize(
    ("kwargs", "word"),
    [
        ({"eye": (0, 0, 0)}, "target"),
        ({"eye": (0, 3, 0)}, "up"),
        ({"eye": (0, 0, 3), "fovy": 0}, "fovy"),
        ({"eye": (0, 0, 3), "fovy": 180}, "fovy"),
        ({"eye": (0, 0, 3), "near": 0}, "near"),
        ({"eye": (0, 0, 3), "near": 2, "far": 1}, "far"),
        ({"eye": (0, np.nan, 3)}, "eye"),
    ],
)
def test_bad_cameras_raise_naming_the_argument(kwargs, word):
    with pytest.raises(ValueError, match=word):
        brdfpy.Camera.perspective(**kwargs)


def test_lights_deliver_what_seed_002_says():
    d = brdfpy.DirectionalLight((0, -2, 0), (1, 2, 3))
    l, e, dist = d.incident((5, 5, 5))
    np.testing.assert_allclose(l, (0, 1, 0)) and np.testing.assert_allclose(e, (1, 2, 3))
    assert dist == float("inf")
    p = brdfpy.PointLight((0, 2, 0), 8.0)
    _, e, dist = p.incident((0, 0, 0))
    assert dist == pytest.approx(2) and e[0] == pytest.approx(8 / 4)
    poly = brdfpy.PointLight((0, 2, 0), 8.0, attenuation=(1, 0.5, 0.25))
    assert poly.incident((0, 0, 0))[1][0] == pytest.approx(8 / (1 + 0.5 * 2 + 0.25 * 4))
    spot = brdfpy.SpotLight((0, 2, 0), (0, -1, 0), 4.0, inner_angle=10, outer_angle=20, attenuation="none")
    assert spot.incident((0, 0, 0))[1][0] == pytest.approx(4)  # on the axis
    assert spot.incident((2, 0, 0)) is None  # 45 degrees off the axis: outside the cone
    for bad in (
        lambda: brdfpy.DirectionalLight((0, 0, 0)),
        lambda: brdfpy.PointLight((0, 0, 0), -1),
        lambda: brdfpy.PointLight((0, 0, 0), 1, attenuation="cubic"),
        lambda: brdfpy.SpotLight((0, 0, 0), (0, -1, 0), 1, inner_angle=30, outer_angle=20),
    ):
        with pytest.raises(ValueError):
            bad()


# -- rendering -------------------------------------------------------------------------------------------


def test_render_returns_every_buffer_with_the_documented_shapes_and_sentinels():
    scene, cam = canonical()
    img = scene.render(cam, 64, 48, outputs="all")
    assert img.shape == (48, 64)
    assert img.rgb.shape == (48, 64, 3) and img.rgb.dtype == np.uint8
    assert img.hdr.shape == (48, 64, 3) and img.hdr.dtype == np.float32
    assert img.depth.shape == (48, 64) and img.depth.dtype == np.float32
    assert img.normal.shape == (48, 64, 3) and img.triangle_id.dtype == np.int64
    bg = ~img.mask
    assert bg[0, 0] and not bg[24, 32]
    assert (img.triangle_id[bg] == -1).all() and (img.depth[bg] == 1).all() and (img.hdr[bg] == 0).all()
    covered = img.mask
    assert (img.depth[covered] < 1).all() and (
        img.triangle_id[covered] < scene.instances[0].mesh.n_faces
    ).all()
    np.testing.assert_allclose(np.linalg.norm(img.normal[covered], axis=2 if False else 1), 1, atol=1e-5)
    assert img.covered_pixels == int(covered.sum())


def test_the_canonical_scene_centre_pixel_is_scene_md_check_value():
    # P = N = (0, 0, 1): ambient 0.05 kd + both lights through the classic formula, recomputed here.
    scene, cam = canonical(4)
    img = scene.render(cam, 64, 64, outputs="all")
    n = np.array([0, 0, 1.0])
    v = np.array([0, 0, 2.0])
    kd = np.array(KD)

    def shade(l: np.ndarray) -> np.ndarray:
        l = l / np.linalg.norm(l)
        h = (l + v / 2) / np.linalg.norm(l + v / 2)
        nl = n @ l
        return kd * max(nl, 0) + (0.5 * max(n @ h, 0) ** 32 if nl > 0 else 0)

    d = np.array([2, 2, 1.0])
    expect = 0.05 * kd + shade(np.ones(3)) + 10 / (d @ d) * shade(d)
    # The pixel centre nearest the middle sees a point within a hair of P.
    np.testing.assert_allclose(img.hdr[32, 32], expect, rtol=2e-3)
    srgb = np.where(expect <= 0.0031308, 12.92 * expect, 1.055 * expect ** (1 / 2.4) - 0.055)
    assert np.abs(img.rgb[32, 32].astype(int) - np.floor(255 * srgb + 0.5)).max() <= 1


def test_tonemap_and_exposure_apply_only_to_rgb():
    scene, cam = canonical()
    a = scene.render(cam, 32, 32, outputs="all")
    b = scene.render(cam, 32, 32, tonemap="aces", exposure=-1, outputs="all")
    np.testing.assert_array_equal(a.hdr, b.hdr)
    assert (a.rgb != b.rgb).any()
    np.testing.assert_array_equal(a.tonemapped("aces", -1), b.rgb)


def test_transforms_place_meshes_and_triangle_ids_count_across_instances():
    scene = brdfpy.Scene()
    m = brdfpy.icosphere(1)
    scene.add(m, "lambert", brdfpy.transforms.translate(-1.5, 0, 0) @ brdfpy.transforms.scale(0.5), ambient=1)
    scene.add(m, "lambert", brdfpy.transforms.translate(1.5, 0, 0) @ brdfpy.transforms.scale(0.5), ambient=1)
    img = scene.render(brdfpy.Camera.orthographic((0, 0, 5), height=2.2), 88, 22, outputs="all")
    ids = img.triangle_id
    left, right = ids[:, :44], ids[:, 44:]
    assert (left[left >= 0] < m.n_faces).all() and (right[right >= 0] >= m.n_faces).all()
    assert left.max() >= 0 and right.max() >= 0 and ids[:, 43:45].max() == -1  # gap in the middle


def test_every_shading_mode_and_supersampling_renders():
    scene, cam = canonical(2)
    base = scene.render(cam, 32, 32, "phong", outputs="all")
    for mode in ("flat", "gouraud", "quadratic"):
        img = scene.render(cam, 32, 32, mode, outputs="all")
        assert img.covered_pixels == base.covered_pixels
    flat = scene.render(cam, 32, 32, "flat", outputs="all")
    assert (flat.rgb != base.rgb).any()
    ss = scene.render(cam, 32, 32, samples=4, outputs="all")
    edge = base.mask & ~np.roll(base.mask, 1, axis=1)
    # Anti-aliased edges take in-between values.
    assert (ss.hdr[edge].sum(axis=1) < base.hdr[edge].sum(axis=1)).any()


def test_shadows_and_ambient_occlusion_darken_and_are_deterministic():
    scene = brdfpy.Scene(ambient_light=0.3)
    scene.add(brdfpy.plane(6.0, 8), "lambert", ambient=1.0)
    scene.add(brdfpy.icosphere(3), "lambert", brdfpy.transforms.translate(0, 1.0, 0), ambient=1.0)
    scene.add_light(brdfpy.DirectionalLight((0, -1, 0), 3.0))
    cam = brdfpy.Camera.perspective((0, 4, 4), (0, 0, 0))
    plain = scene.render(cam, 48, 48, outputs="all")
    shadowed = scene.render(cam, 48, 48, shadows=True, outputs="all")
    assert shadowed.hdr.sum() < plain.hdr.sum()
    ao = scene.render(cam, 48, 48, ao={"samples": 16, "per_pixel": True}, outputs="all")
    assert ao.hdr.sum() < plain.hdr.sum()
    np.testing.assert_array_equal(
        ao.hdr, scene.render(cam, 48, 48, ao={"samples": 16, "per_pixel": True}, outputs="all").hdr
    )
    with pytest.raises(ValueError, match="ao"):
        scene.render(cam, 8, 8, ao={"radius": 1}, outputs="all")


def test_output_is_bit_identical_at_any_thread_count():
    scene, cam = canonical(4)
    try:
        brdfpy.set_num_threads(1)
        one = scene.render(cam, 97, 61, shadows=True, outputs="all")
        brdfpy.set_num_threads(3)
        three = scene.render(cam, 97, 61, shadows=True, outputs="all")
    finally:
        brdfpy.set_num_threads(None)
    np.testing.assert_array_equal(one.hdr, three.hdr)
    np.testing.assert_array_equal(one.triangle_id, three.triangle_id)


def test_progress_is_reported_in_increasing_fractions_up_to_one_and_errors_propagate():
    scene, cam = canonical()
    seen: list[float] = []
    scene.render(cam, 64, 200, progress=seen.append, outputs="all")
    assert seen and seen[-1] == 1.0 and seen == sorted(seen)

    def boom(_f: float) -> None:
        raise KeyError("stop")

    with pytest.raises(KeyError):
        scene.render(cam, 64, 64, progress=boom, outputs="all")


def test_the_gil_is_released_while_rendering():
    scene, cam = canonical(6)
    ticks = 0
    done = threading.Event()

    def count() -> None:
        nonlocal ticks
        while not done.is_set():
            ticks += 1

    t = threading.Thread(target=count)
    t.start()
    try:
        scene.render(cam, 800, 600, outputs="all")
    finally:
        done.set()
        t.join()
    # With the GIL held for the whole render, the counting thread would barely run.
    assert ticks > 1000


def test_image_saves_png_through_pillow_and_has_a_jupyter_repr(tmp_path):
    scene, cam = canonical()
    img = scene.render(cam, 40, 30, outputs="all")
    path = tmp_path / "out.png"
    img.save(path)
    with PILImage.open(path) as im:
        assert im.size == (40, 30) and im.mode == "RGB"
        np.testing.assert_array_equal(np.asarray(im), img.rgb)
    with PILImage.open(io.BytesIO(img._repr_png_())) as im:
        assert im.format == "PNG"


@pytest.mark.parametrize(
    ("kwargs", "exc", "word"),
    [
        ({"width": 0}, ValueError, "width"),
        ({"height": 100_000}, ValueError, "height"),
        ({"width": 16384, "height": 16384, "samples": 4}, ValueError, "width"),
        ({"width": 10.5}, TypeError, "width"),
        ({"shading": "smooth"}, ValueError, "shading"),
        ({"samples": 3}, ValueError, "samples"),
        ({"tonemap": "filmic"}, ValueError, "tonemap"),
        ({"exposure": float("nan")}, ValueError, "exposure"),
        ({"progress": 3}, TypeError, "progress"),
    ],
)
def test_bad_render_arguments_raise_naming_the_argument(kwargs, exc, word):
    scene, cam = canonical(1)
    args = {"width": 16, "height": 16, **kwargs}
    with pytest.raises(exc, match=word):
        scene.render(cam, **args, outputs="all")


def test_bad_scene_contents_raise_naming_the_argument():
    scene = brdfpy.Scene()
    cam = brdfpy.Camera()
    with pytest.raises(ValueError, match="scene"):
        scene.render(cam, 8, 8, outputs="all")
    with pytest.raises(ValueError, match="transform"):
        scene.add(brdfpy.icosphere(0), "lambert", np.zeros((4, 4)))
    with pytest.raises(ValueError, match="transform"):
        scene.add(brdfpy.icosphere(0), "lambert", np.full((4, 4), np.nan))
    with pytest.raises(TypeError, match="material"):
        scene.add(brdfpy.icosphere(0), 42)
    with pytest.raises(ValueError, match="ambient"):
        scene.add(brdfpy.icosphere(0), "lambert", ambient=-1)
    with pytest.raises(ValueError, match="background"):
        brdfpy.Scene(background=np.inf)
    with pytest.raises(TypeError, match="light"):
        scene.add_light("sun")
