"""Bad input to meshes, loaders and renders: a clear exception naming the problem (ValueError,
TypeError or OSError), or a documented skip -- never a crash, a hang or NaN in the image."""

from __future__ import annotations

import math
from pathlib import Path

import brdfpy
import numpy as np
import pytest

TRI = [[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]


def small_scene() -> brdfpy.Scene:
    s = brdfpy.Scene()
    s.add(brdfpy.icosphere(1), "lambert")
    s.add_light(brdfpy.DirectionalLight((0, 0, -1)))
    return s


CAM = brdfpy.Camera.perspective((0, 0, 3))

# ------------------------------------------------------------------------------------------ meshes


@pytest.mark.parametrize(
    ("vertices", "faces", "match"),
    [
        (np.zeros((0, 3)), np.zeros((0, 3), int), "vertices|empty"),
        (TRI, np.zeros((0, 3), int), "faces"),
        (TRI, [[0, 1, 3]], "faces.*(past|index|range)"),
        (TRI, [[0, 1, -1]], "faces"),
        ([[0.0, 0, 0], [1, 0, math.nan], [0, 1, 0]], [[0, 1, 2]], "vertices.*(finite|nan|NaN)"),
        ([[0.0, 0, 0], [1, 0, math.inf], [0, 1, 0]], [[0, 1, 2]], "vertices.*(finite|inf)"),
        (np.zeros((3, 2)), [[0, 1, 2]], "vertices.*shape|vertices.*3"),
        (TRI, [[0, 1]], "faces.*shape|faces.*3"),
    ],
    ids=["no vertices", "no faces", "index past end", "negative index", "nan", "inf", "2d", "pairs"],
)
def test_bad_meshes_raise_value_error_naming_the_argument(
    vertices: object, faces: object, match: str
) -> None:
    with pytest.raises(ValueError, match=match):
        brdfpy.Mesh(vertices, faces)


def test_non_integer_or_non_numeric_faces_raise() -> None:
    with pytest.raises((TypeError, ValueError), match="faces"):
        brdfpy.Mesh(TRI, [[0.0, 1.5, 2.0]])
    with pytest.raises((TypeError, ValueError), match="vertices"):
        brdfpy.Mesh([["a", "b", "c"]] * 3, [[0, 1, 2]])


def test_bad_normals_raise() -> None:
    with pytest.raises(ValueError, match="normals"):
        brdfpy.Mesh(TRI, [[0, 1, 2]], normals=[[0, 0, 1]] * 2)
    with pytest.raises(ValueError, match="normals"):
        brdfpy.Mesh(TRI, [[0, 1, 2]], normals=[[0, 0, math.nan]] * 3)
    with pytest.raises((ValueError, TypeError), match="weighting"):
        brdfpy.Mesh(TRI, [[0, 1, 2]]).compute_normals("bogus")


def test_degenerate_triangles_are_skipped_and_render_nothing() -> None:
    # documented: zero-area faces are kept in the mesh and cover no pixel; finite normals everywhere
    v = [[0.0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 0, 0], [0, 1, 0]]
    m = brdfpy.Mesh(v, [[0, 1, 2], [0, 3, 4], [0, 1, 4]])  # collinear, repeated vertex, a real one
    assert np.isfinite(m.normals).all()
    assert m.stats()["degenerate_triangles"] == 2
    s = brdfpy.Scene()
    s.add(m, "lambert")
    s.add_light(brdfpy.DirectionalLight((0, 0, -1)))
    img = s.render(
        brdfpy.Camera.orthographic((0.5, 0.5, 2), (0.5, 0.5, 0), height=2.0), 40, 40, outputs="all"
    )
    ids = np.asarray(img.triangle_id)
    assert set(np.unique(ids).tolist()) == {-1, 2}
    assert np.isfinite(np.asarray(img.hdr)).all()


# ------------------------------------------------------------------------------------------ renders


@pytest.mark.parametrize(
    ("w", "h", "match"),
    [
        (0, 10, "width"),
        (10, 0, "height"),
        (-5, 10, "width"),
        (16385, 10, "width"),
        (
            16384,
            16384,
            "samples|2\\^28|too large|limit",
        ),  # 2^28 samples: at the limit, but samples=4 exceeds it
    ],
)
def test_zero_negative_or_absurd_sizes_are_refused(w: int, h: int, match: str) -> None:
    samples = 4 if (w, h) == (16384, 16384) else 1
    with pytest.raises(ValueError, match=match):
        small_scene().render(CAM, w, h, samples=samples)


def test_absurd_size_is_refused_without_allocating() -> None:
    # 16384 x 16384 x 16 samples would need ~100 GB: refused up front, quickly
    with pytest.raises(ValueError):
        small_scene().render(CAM, 16384, 16384, samples=16)


@pytest.mark.parametrize("w", [1.5, "64", None])
def test_non_integer_sizes_raise_type_error(w: object) -> None:
    with pytest.raises(TypeError, match="width"):
        small_scene().render(CAM, w, 10)  # type: ignore[arg-type]


def test_unknown_options_raise() -> None:
    s = small_scene()
    with pytest.raises(ValueError, match="shading"):
        s.render(CAM, 8, 8, shading="toon-shading")
    with pytest.raises(ValueError, match="samples"):
        s.render(CAM, 8, 8, samples=3)
    # the message must name the render argument the user wrote, ``tonemap``
    with pytest.raises(ValueError, match="tonemap"):
        s.render(CAM, 8, 8, tonemap="bogus")
    with pytest.raises(TypeError, match="camera"):
        s.render("camera", 8, 8)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"scene|mesh"):
        brdfpy.Scene().render(CAM, 8, 8)


def test_bad_transforms_and_colours_raise() -> None:
    s = brdfpy.Scene()
    m = brdfpy.icosphere(0)
    with pytest.raises(ValueError, match="transform"):
        s.add(m, "lambert", np.zeros((4, 4)))
    with pytest.raises(ValueError, match="transform"):
        s.add(m, "lambert", np.full((4, 4), np.nan))
    with pytest.raises(ValueError, match="transform"):
        s.add(m, "lambert", np.eye(3))
    with pytest.raises(ValueError, match="ambient"):
        s.add(m, "lambert", ambient=-1)
    with pytest.raises(ValueError, match="emission"):
        s.add(m, "lambert", emission=(0, math.nan, 0))
    with pytest.raises(TypeError, match="material"):
        s.add(m, 42)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="background"):
        brdfpy.Scene(background=math.inf)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: brdfpy.Camera.perspective((0, 0, 3), (0, 0, 3)), "eye|target"),
        (lambda: brdfpy.Camera.perspective((0, 0, 3), up=(0, 0, 1)), "up"),
        (lambda: brdfpy.Camera.perspective((0, 0, 3), fovy=0), "fovy"),
        (lambda: brdfpy.Camera.perspective((0, 0, 3), fovy=180), "fovy"),
        (lambda: brdfpy.Camera.perspective((0, 0, 3), near=0), "near"),
        (lambda: brdfpy.Camera.perspective((0, 0, 3), near=2, far=1), "near|far"),
        (lambda: brdfpy.Camera.perspective((0, math.nan, 3)), "eye"),
        (lambda: brdfpy.Camera.orthographic((0, 0, 3), height=0), "height"),
        (lambda: brdfpy.DirectionalLight((0, 0, 0)), "direction"),
        (lambda: brdfpy.DirectionalLight((0, 0, -1), color=-1), "color"),
        (lambda: brdfpy.PointLight((0, 0, math.inf)), "position"),
        (lambda: brdfpy.PointLight((0, 0, 1), attenuation="cubic"), "attenuation"),
        (lambda: brdfpy.PointLight((0, 0, 1), attenuation=(0, 0, 0)), "attenuation|c1|coefficient"),
        (lambda: brdfpy.SpotLight((0, 0, 1), (0, 0, -1), inner_angle=40, outer_angle=30), "inner_angle"),
        (lambda: brdfpy.SpotLight((0, 0, 1), (0, 0, -1), outer_angle=180), "outer_angle"),
    ],
)
def test_bad_cameras_and_lights_raise_value_error(make: object, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        make()  # type: ignore[operator]


def test_extreme_but_finite_geometry_renders_finite_images() -> None:
    # huge and tiny coordinates, a vertex exactly at the eye, one on the camera plane: no NaN, no crash
    v = np.array([[-1e30, -1e30, -1], [1e30, -1e30, -1], [0, 1e30, -1], [0, 0, 3], [1, 0, 3], [1e-30, 0, 0]])
    f = np.array([[0, 1, 2], [3, 4, 5], [0, 3, 4]])
    s = brdfpy.Scene()
    s.add(brdfpy.Mesh(v, f, normals=np.tile([0, 0, 1.0], (6, 1))), "lambert")
    s.add_light(brdfpy.PointLight((0, 0, 1), 1.0))
    for shading in ("flat", "gouraud", "phong", "quadratic"):
        img = s.render(CAM, 32, 24, shading=shading, outputs="all")
        assert np.isfinite(np.asarray(img.hdr)).all(), shading
        assert np.isfinite(np.asarray(img.depth)).all(), shading


# ------------------------------------------------------------------------------------------- files


BAD_FILES = {
    "empty.obj": b"",
    "comments_only.obj": b"# nothing here\n",
    "bad_number.obj": b"v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n",
    "index_past_end.obj": b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n",
    "nan.obj": b"v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n",
    "empty.ply": b"",
    "not_ply.ply": b"solid cube\nfacet normal 0 0 1\n",
    "truncated_header.ply": b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n",
    "truncated_body.ply": (
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        b"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"
    ),
    "truncated_binary.ply": (
        b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        b"property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        + b"\x00"
        * 20
    ),
    "index_past_end.ply": (
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        b"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n"
    ),
    "no_faces.ply": (
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        b"end_header\n0 0 0\n1 0 0\n0 1 0\n"
    ),
    "huge_count.ply": (
        b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
        b"property float y\nproperty float z\nend_header\n" + b"\x00" * 24
    ),
    "binary_garbage.obj": bytes(range(256)) * 4,
}


@pytest.mark.parametrize("name", sorted(BAD_FILES))
def test_malformed_files_raise_naming_the_file(tmp_path: Path, name: str) -> None:
    p = tmp_path / name
    p.write_bytes(BAD_FILES[name])
    with pytest.raises((ValueError, OSError)) as info:
        brdfpy.load_mesh(p)
    assert name in str(info.value) or "path" in str(info.value), str(info.value)


def test_missing_files_directories_and_unknown_extensions(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError):
        brdfpy.load_mesh(tmp_path / "missing.obj")
    with pytest.raises(OSError):
        brdfpy.load_mesh(tmp_path)
    p = tmp_path / "mesh.stl"
    p.write_bytes(b"solid x\nendsolid x\n")
    with pytest.raises(ValueError, match=r"stl|extension|format"):
        brdfpy.load_mesh(p)
