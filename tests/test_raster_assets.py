"""Real meshes from ``../shared/assets/meshes`` (skipped when that folder is absent): loading OBJ and PLY
against ``meshes.json``'s counts and properties, and a render compared with the reference rasterizer."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import brdfpy
import numpy as np
import pytest

from raster_oracle import bridge as rb

ASSETS = Path(__file__).resolve().parents[1] / ".." / "shared" / "assets" / "meshes"
pytestmark = pytest.mark.skipif(not (ASSETS / "meshes.json").is_file(), reason="../shared/assets absent")


@pytest.fixture(scope="module")
def table() -> dict[str, Any]:
    return json.loads((ASSETS / "meshes.json").read_text())


@pytest.mark.parametrize("name", ["garland_cow", "hoppe_fandisk", "cyberware_horse"])
def test_assets_load_with_the_documented_counts(name: str, table: dict[str, Any]) -> None:
    info = table[name]
    for fname in info["files"]:
        path = ASSETS / fname
        if not path.is_file():
            continue
        m = brdfpy.load_mesh(path, orient="keep")  # the horse is wound inward: measured as it is
        assert m.n_faces == info["triangles"], fname
        assert m.n_vertices == info["vertices"], fname
        lo, hi = m.bounds()
        np.testing.assert_allclose(lo, info["bbox_min"], atol=1e-5)
        np.testing.assert_allclose(hi, info["bbox_max"], atol=1e-5)
        st = m.stats()
        assert (
            st["watertight"] == info["watertight"] and st["winding_consistent"] == info["winding_consistent"]
        )
        if name == "cyberware_horse":
            assert st["signed_volume"] < 0  # wound inward (README "Notes that matter for tests")
        elif info["watertight"]:
            assert st["signed_volume"] > 0


def test_obj_and_ply_of_the_cow_are_the_same_mesh() -> None:
    if not (ASSETS / "garland_cow.obj").is_file():
        pytest.skip("garland_cow.obj absent")
    a, b = brdfpy.load_mesh(ASSETS / "garland_cow.obj"), brdfpy.load_mesh(ASSETS / "garland_cow.ply")
    # the same triangles, in the same order with the same corners (the OBJ loader may number the vertices
    # differently: in order of first use)
    np.testing.assert_allclose(a.vertices[a.faces.astype(int)], b.vertices[b.faces.astype(int)], atol=1e-6)


@pytest.mark.slow
def test_cow_render_matches_reference() -> None:
    mesh = brdfpy.load_mesh(ASSETS / "garland_cow.ply")
    obj = rb.Obj(
        np.asarray(mesh.vertices),
        np.asarray(mesh.faces),
        np.asarray(mesh.normals),
        model="cook_torrance",
        params={"kd": (0.5, 0.4, 0.3), "ks": 0.5, "roughness": 0.35},
        ambient=0.03,
    )
    lights = [
        rb.Light("directional", {"direction": (-0.4, -1.0, -0.6), "color": 2.0}),
        rb.Light("point", {"position": (1.0, 1.0, 1.5), "intensity": 3.0}),
    ]
    spec = rb.Spec(
        [obj], lights, rb.Cam("perspective", {"eye": (0.6, 0.5, 1.6), "target": (0, 0, 0), "fovy": 40})
    )
    img, ref = rb.render_both(spec, 64, 48, "phong")
    rb.assert_matches(img.hdr, ref.hdr, img.triangle_id, ref, spec, "cow phong hdr")
    assert ref.covered.sum() > 300
