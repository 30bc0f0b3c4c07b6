"""Standing meshes up and turning them outward: `--up`/`--rotate` in `brdfpy render`, `up_to_y`,
`load_mesh(up=)`, and the inward-winding warning of `Mesh.from_any` / `load_mesh` (`orient=`)."""

from __future__ import annotations

import types
import warnings
from pathlib import Path

import brdfpy
import numpy as np
import pytest
from brdfpy import cli, render_cmd
from brdfpy.transforms import UP_AXES, up_to_y

ASSETS = Path(__file__).resolve().parents[2] / "shared" / "assets" / "meshes"


def asset(name: str) -> Path:
    path = ASSETS / name
    if not path.is_file():
        pytest.skip(f"{name} absent (the shared test assets are not beside this work tree)")
    return path


@pytest.mark.parametrize("up", UP_AXES)
def test_up_to_y_is_a_proper_rotation_lifting_the_named_axis_to_plus_y(up: str) -> None:
    m = up_to_y(up)
    axis = {"x": 0, "y": 1, "z": 2}[up[-1]]
    v = np.zeros(4)
    v[axis] = -1.0 if up.startswith("-") else 1.0
    np.testing.assert_array_equal(m @ v, [0, 1, 0, 0])
    np.testing.assert_allclose(m[:3, :3] @ m[:3, :3].T, np.eye(3))
    assert np.linalg.det(m[:3, :3]) == pytest.approx(1.0)


def test_z_up_files_have_their_front_minus_y_turned_to_plus_z() -> None:
    # Blender / CAD convention (front view looks along +y) → glTF's (front faces +z).
    np.testing.assert_array_equal(up_to_y("z") @ [0, -1, 0, 0], [0, 0, 1, 0])
    np.testing.assert_array_equal(up_to_y("+Z"), up_to_y("z"))
    with pytest.raises(ValueError, match="up: expected one of"):
        up_to_y("w")
    with pytest.raises(TypeError, match="up:"):
        up_to_y(2)  # type: ignore[arg-type]


def test_load_mesh_up_z_stands_the_teapot_up() -> None:
    path = asset("newell_teapot_n96.ply")
    lying = brdfpy.load_mesh(path)
    standing = brdfpy.load_mesh(path, up="z")
    (lo0, hi0), (lo1, hi1) = lying.bounds(), standing.bounds()
    # Its height (file z: 0.75) is now along y, its depth (file y) along z; the winding is kept.
    assert hi1[1] - lo1[1] == pytest.approx(hi0[2] - lo0[2], rel=1e-6)
    assert hi1[2] - lo1[2] == pytest.approx(hi0[1] - lo0[1], rel=1e-6)
    assert standing.stats()["signed_volume"] == pytest.approx(lying.stats()["signed_volume"], rel=1e-4)


def _silhouette(png: Path) -> tuple[int, int]:
    """(width, height) in pixels of what is not background in a render without a floor."""
    from PIL import Image

    rgb = np.asarray(Image.open(png).convert("RGB")).astype(int)
    covered = (rgb - rgb[0, 0]).__abs__().sum(axis=-1) > 12
    rows, cols = np.nonzero(covered)
    return int(cols.max() - cols.min() + 1), int(rows.max() - rows.min() + 1)


def test_a_z_up_teapot_stands_up_with_up_z_in_the_cli(tmp_path: Path) -> None:
    path = asset("newell_teapot_n96.ply")
    base = ["render", "--mesh", str(path), "--no-floor", "-q", "--size", "320x240", "--samples", "1"]
    base += ["--no-shadows", "--eye", "0,0,4", "--target", "0,0.4,0"]
    assert cli.main([*base, "-o", str(tmp_path / "lying.png")]) == 0
    assert cli.main([*base, "--up", "z", "-o", str(tmp_path / "standing.png")]) == 0
    w0, h0 = _silhouette(tmp_path / "lying.png")
    w1, h1 = _silhouette(tmp_path / "standing.png")
    # Seen from the front, standing: spout to handle (1.61) over its height (0.75); lying on its back, the
    # camera sees it from above: spout to handle over the body's depth (1.0).
    assert w1 / h1 == pytest.approx(1.61 / 0.75, rel=0.12)
    assert w0 / h0 == pytest.approx(1.61 / 1.0, rel=0.12)


def test_rotate_turns_the_mesh_about_the_vertical_and_about_any_axis(tmp_path: Path) -> None:
    np.testing.assert_allclose(
        render_cmd.stand_transform("y", ["180"]) @ [0, 0, 1, 0], [0, 0, -1, 0], atol=1e-12
    )
    np.testing.assert_allclose(
        render_cmd.stand_transform("z", ["x:90"]) @ [0, 0, 1, 0], [0, 0, 1, 0], atol=1e-12
    )
    np.testing.assert_allclose(
        render_cmd.stand_transform("y", ["0,0,1:90", "y:90"]) @ [1, 0, 0, 0], [0, 1, 0, 0], atol=1e-12
    )
    for bad in ("north", "q:90", "0,0,0:90", "x:inf"):
        with pytest.raises(ValueError, match="--rotate"):
            render_cmd.parse_rotation(bad)
    # Negative values after --up and --rotate reach the parser.
    out = tmp_path / "cow.png"
    args = ["render", "--mesh", "builtin:cow", "--up", "-z", "--rotate", "-90", "-q", "--size", "64x48"]
    assert cli.main([*args, "--samples", "1", "-o", str(out)]) == 0 and out.is_file()


def test_a_closed_mesh_wound_inward_is_reported_with_the_fix_and_orient_fixes_it() -> None:
    sphere = brdfpy.icosphere(2)
    inward = types.SimpleNamespace(vertices=sphere.vertices, faces=sphere.faces[:, ::-1])
    with pytest.warns(brdfpy.InwardMeshWarning, match=r"flip_winding\(\)"):
        m = brdfpy.Mesh.from_any(inward)
    assert m.is_inward() and m.stats()["signed_volume"] < 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fixed = brdfpy.Mesh.from_any(inward, orient="outward")
        kept = brdfpy.Mesh.from_any(inward, orient="keep")
        # open meshes and outward meshes are never reported
        brdfpy.Mesh.from_any(types.SimpleNamespace(vertices=sphere.vertices, faces=sphere.faces[:40, ::-1]))
        brdfpy.Mesh.from_any(types.SimpleNamespace(vertices=sphere.vertices, faces=sphere.faces))
    assert not fixed.is_inward() and fixed.stats()["signed_volume"] > 0
    assert kept.is_inward()
    # a Mesh passes through, or is returned as a turned copy with orient="outward"
    assert brdfpy.Mesh.from_any(m) is m
    turned = brdfpy.Mesh.from_any(m, orient="outward")
    assert turned is not m and not turned.is_inward() and m.is_inward()
    with pytest.raises(ValueError, match="orient: expected one of"):
        brdfpy.Mesh.from_any(inward, orient="flip")  # type: ignore[arg-type]


def test_the_inward_horse_warns_on_load_and_renders_lit_once_turned(tmp_path: Path) -> None:
    path = asset("cyberware_horse.ply")
    with pytest.warns(brdfpy.InwardMeshWarning, match="cyberware_horse.ply"):
        brdfpy.load_mesh(path)
    horse = brdfpy.load_mesh(path, up="z", orient="outward")
    assert horse.stats()["signed_volume"] > 0

    def render(mesh: brdfpy.Mesh) -> tuple[float, float]:
        """(mean 8-bit value, mean depth) of the covered pixels, lit from the camera, with shadows."""
        scene = brdfpy.Scene(ambient_light=0.0)
        center, radius = mesh.bounding_sphere()
        scene.add(mesh, brdfpy.model("lambert", kd=0.8))
        scene.add_light(brdfpy.DirectionalLight((0, 0, -1), 3.0))
        cam = brdfpy.Camera.framing(center, radius, (0, 0, 1))
        img = scene.render(cam, 96, 96, shadows=True)
        return float(np.asarray(img.rgb)[img.mask].mean()), float(np.asarray(img.depth)[img.mask].mean())

    lit, near = render(horse)
    dark, far = render(brdfpy.load_mesh(path, up="z", orient="keep"))
    # inward, culling keeps the inside of the far side: it is seen deeper, in the shadow of the near side
    assert far > near and lit > 3 * dark + 10
