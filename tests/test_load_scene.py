"""brdfpy.load_scene: glTF 2.0 scenes (written here by pygltflib, an independent writer), OBJ + MTL and STL
files written by hand, mapped onto brdfpy's models, lights and cameras as brdfpy.assets documents; the
glTF specification's Appendix B BRDF transcribed in NumPy as the reference for the material mapping."""

from __future__ import annotations

import base64
import math
import struct
from pathlib import Path
from typing import Any

import brdfpy
import numpy as np
import pytest
from brdfpy.assets import TexturesNotAppliedWarning, load_scene

pygltflib = pytest.importorskip("pygltflib")

# -- an independent glTF writer -----------------------------------------------------------------------------

# A closed, asymmetric wedge (a mirrored copy differs from it), counter-clockwise outward.
WEDGE_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.6, 0.7, 0.8]], dtype=np.float32)
WEDGE_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 4], [1, 4, 3], [2, 3, 4]], dtype=np.uint32)


def _signed_volume(v: np.ndarray, f: np.ndarray) -> float:
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6)


def test_the_wedge_is_closed_and_outward() -> None:
    assert _signed_volume(WEDGE_V, WEDGE_F) > 0


def _quat_y(deg: float) -> list[float]:
    t = math.radians(deg) / 2
    return [0.0, math.sin(t), 0.0, math.cos(t)]


def _trs(t: Any = (0, 0, 0), q: Any = (0, 0, 0, 1), s: Any = (1, 1, 1)) -> np.ndarray:
    """T·R·S of glTF 2.0 §3.5.3 in NumPy (quaternion x, y, z, w)."""
    x, y, z, w = q
    r = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    m = np.eye(4)
    m[:3, :3] = r @ np.diag(s)
    m[:3, 3] = t
    return m


class Writer:
    """Builds a glTF document with pygltflib: meshes from arrays, nodes, materials, cameras, lights."""

    def __init__(self) -> None:
        self.g = pygltflib.GLTF2(asset=pygltflib.Asset(version="2.0"))
        self.blob = b""

    def _view(self, data: bytes, target: int | None = None) -> int:
        pad = (-len(self.blob)) % 4
        self.blob += b"\0" * pad
        self.g.bufferViews.append(
            pygltflib.BufferView(buffer=0, byteOffset=len(self.blob), byteLength=len(data), target=target)
        )
        self.blob += data
        return len(self.g.bufferViews) - 1

    def accessor(self, a: np.ndarray, kind: str) -> int:
        ctype = {np.dtype(np.float32): pygltflib.FLOAT, np.dtype(np.uint32): pygltflib.UNSIGNED_INT}[a.dtype]
        flat = a.reshape(len(a), -1) if a.ndim > 1 else a
        view = self._view(a.tobytes())
        acc = pygltflib.Accessor(bufferView=view, componentType=ctype, count=len(flat), type=kind)
        if kind == "VEC3" and a.dtype == np.float32:
            acc.min, acc.max = a.min(axis=0).tolist(), a.max(axis=0).tolist()
        self.g.accessors.append(acc)
        return len(self.g.accessors) - 1

    def mesh(self, v: np.ndarray, f: np.ndarray, material: int | None = None, **attrs: np.ndarray) -> int:
        a = pygltflib.Attributes(POSITION=self.accessor(v.astype(np.float32), "VEC3"))
        for name, arr in attrs.items():
            kind = {2: "VEC2", 3: "VEC3", 4: "VEC4"}[arr.shape[1]]
            setattr(a, name, self.accessor(arr.astype(np.float32), kind))
        ind = self.accessor(f.astype(np.uint32).reshape(-1), "SCALAR")
        self.g.meshes.append(
            pygltflib.Mesh(primitives=[pygltflib.Primitive(attributes=a, indices=ind, material=material)])
        )
        return len(self.g.meshes) - 1

    def node(self, **kw: Any) -> int:
        self.g.nodes.append(pygltflib.Node(**kw))
        return len(self.g.nodes) - 1

    def material(self, **kw: Any) -> int:
        self.g.materials.append(pygltflib.Material(**kw))
        return len(self.g.materials) - 1

    def lights(self, lights: list[dict[str, Any]]) -> None:
        self.g.extensions["KHR_lights_punctual"] = {"lights": lights}
        self.g.extensionsUsed.append("KHR_lights_punctual")

    def save(self, path: Path, roots: list[int], form: str = "glb") -> Path:
        self.g.scenes = [pygltflib.Scene(nodes=roots)]
        self.g.scene = 0
        if form == "glb":
            self.g.buffers = [pygltflib.Buffer(byteLength=len(self.blob))]
            self.g.set_binary_blob(self.blob)
            self.g.save_binary(str(path))
        elif form == "gltf":
            bin_path = path.with_suffix(".bin")
            bin_path.write_bytes(self.blob)
            self.g.buffers = [pygltflib.Buffer(byteLength=len(self.blob), uri=bin_path.name)]
            self.g.save_json(str(path))
        else:  # data URI
            uri = "data:application/octet-stream;base64," + base64.b64encode(self.blob).decode()
            self.g.buffers = [pygltflib.Buffer(byteLength=len(self.blob), uri=uri)]
            self.g.save_json(str(path))
        return path


def _quiet_load(path: Path, **kw: Any) -> tuple[brdfpy.Scene, list[brdfpy.Camera]]:
    return load_scene(path, **kw)


def _render(scene: brdfpy.Scene, cam: brdfpy.Camera, size: int = 96) -> np.ndarray:
    return scene.render(cam, size, size, outputs=("hdr", "depth")).hdr


# -- node hierarchy, winding ---------------------------------------------------------------------------------


def test_node_hierarchy_composes_parent_times_child(tmp_path: Path) -> None:
    w = Writer()
    m = w.mesh(WEDGE_V, WEDGE_F)
    child = w.node(mesh=m, translation=[0, 0.5, 0], scale=[2, 1, 0.5])
    mid = w.node(children=[child], rotation=_quat_y(90))
    root = w.node(children=[mid], translation=[1, 2, 3])
    scene, _ = _quiet_load(w.save(tmp_path / "h.glb", [root]))
    expected = _trs(t=(1, 2, 3)) @ _trs(q=_quat_y(90)) @ _trs(t=(0, 0.5, 0), s=(2, 1, 0.5))
    (part,) = scene.asset.parts  # type: ignore[attr-defined]
    np.testing.assert_allclose(part.instance.transform, expected, atol=1e-6)
    # The world-space box is that of the transformed vertices.
    pts = (np.c_[WEDGE_V, np.ones(5)] @ expected.T)[:, :3]
    lo, hi = scene.bounds()
    np.testing.assert_allclose(lo, pts.min(axis=0), atol=1e-5)
    np.testing.assert_allclose(hi, pts.max(axis=0), atol=1e-5)


def test_a_negative_scale_node_renders_as_the_mirrored_geometry(tmp_path: Path) -> None:
    # glTF §3.7.2.1: a node whose world matrix has a negative determinant flips the winding, so the mirrored
    # wedge shows its outside. The reference is the mirrored geometry written out with its faces reversed.
    mirror = np.diag([-1.0, 1.0, 1.0])
    w1 = Writer()
    n1 = w1.node(mesh=w1.mesh(WEDGE_V, WEDGE_F), scale=[-1, 1, 1])
    a = w1.save(tmp_path / "neg.glb", [n1])
    w2 = Writer()
    mv = (WEDGE_V @ mirror.T).astype(np.float32)
    n2 = w2.node(mesh=w2.mesh(mv, WEDGE_F[:, ::-1].copy()))
    b = w2.save(tmp_path / "mirrored.glb", [n2])
    w3 = Writer()  # the mirrored positions with the winding NOT reversed: inside out
    n3 = w3.node(mesh=w3.mesh(mv, WEDGE_F))
    c = w3.save(tmp_path / "inside_out.glb", [n3])
    cam = brdfpy.Camera.perspective((-1.2, 1.5, 2.5), (-0.3, 0.3, 0.3), fovy=40)
    imgs = []
    for p in (a, b, c):
        scene, _ = _quiet_load(p, lights="default")
        scene.lights = [brdfpy.DirectionalLight((0.3, -1, -0.6), intensity=3.0)]
        imgs.append(_render(scene, cam))
    assert imgs[0].max() > 0.05
    np.testing.assert_allclose(imgs[0], imgs[1], atol=2e-3)
    assert np.abs(imgs[0] - imgs[2]).max() > 0.05  # the comparison can fail


# -- Appendix B ---------------------------------------------------------------------------------------------


def appendix_b(
    l: np.ndarray, v: np.ndarray, n: np.ndarray, base: np.ndarray, metal: float, rough: float
) -> np.ndarray:
    """glTF 2.0 Appendix B ("Metal BRDF and Dielectric BRDF", its full code):
    mix(dielectric_brdf, metal_brdf, metallic), float64, per channel."""
    h = l + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    nl, nv, nh = (np.sum(n * x, axis=-1) for x in (l, v, h))
    vh = np.abs(np.sum(v * h, axis=-1))
    a = rough**2
    d = a * a * (nh > 0) / (np.pi * (nh * nh * (a * a - 1) + 1) ** 2)
    vis = (
        (nl > 0)
        * (nv > 0)
        / (
            np.abs(nl) * np.sqrt(nv * nv * (1 - a * a) + a * a)
            + np.abs(nv) * np.sqrt(nl * nl * (1 - a * a) + a * a)
        )
        / 2
    )
    spec = (v_d := vis * d)[..., None]
    weight = (1 - vh) ** 5
    f_d = 0.04 + (1 - 0.04) * weight  # dielectric: fresnel_mix(ior 1.5)
    dielectric = (1 - f_d)[..., None] * base / np.pi + f_d[..., None] * spec
    f_m = base + (1 - base) * weight[..., None]  # conductor_fresnel(f0 = baseColor)
    metal_brdf = f_m * spec
    out = (1 - metal) * dielectric + metal * metal_brdf
    del v_d
    return out * ((nl > 0) & (nv > 0))[..., None]


@pytest.mark.parametrize("metal, rough", [(0.0, 0.5), (0.3, 0.6), (1.0, 0.25), (0.7, 0.9)])
def test_metallic_roughness_is_appendix_b_but_for_the_diffuse_fresnel_weight(
    tmp_path: Path, metal: float, rough: float
) -> None:
    base = np.array([0.8, 0.5, 0.2])
    w = Writer()
    mat = w.material(
        pbrMetallicRoughness=pygltflib.PbrMetallicRoughness(
            baseColorFactor=[*base.tolist(), 1.0], metallicFactor=metal, roughnessFactor=rough
        )
    )
    root = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F, material=mat))
    scene, _ = _quiet_load(w.save(tmp_path / "m.glb", [root]))
    model = scene.instances[0].material
    assert model.name == "cook_torrance"
    rng = np.random.default_rng(5)
    n = np.array([0.0, 0.0, 1.0])
    l = rng.normal(size=(400, 3))
    v = rng.normal(size=(400, 3))
    l[:, 2], v[:, 2] = np.abs(l[:, 2]) + 0.05, np.abs(v[:, 2]) + 0.05
    l /= np.linalg.norm(l, axis=1, keepdims=True)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    ours = model.eval(l, v, n).astype(np.float64)
    ref = appendix_b(l, v, n, base, metal, rough)
    # The documented difference: brdfpy's diffuse kd/pi is not weighted by 1 - F_d(v.h).
    h = (l + v) / np.linalg.norm(l + v, axis=1, keepdims=True)
    f_d = 0.04 + 0.96 * (1 - np.abs(np.sum(v * h, axis=1))) ** 5
    missing = (1 - metal) * f_d[:, None] * base / np.pi
    np.testing.assert_allclose(ours, ref + missing, rtol=2e-4, atol=1e-6)
    if metal < 1:  # ... and it is a real difference (the test can fail), at least 4 % of the diffuse
        assert (missing >= 0.04 * (1 - metal) * base / np.pi - 1e-9).all()
        assert np.abs(ours - ref).max() > 1e-3


def test_factors_emission_and_default_material(tmp_path: Path) -> None:
    w = Writer()
    w.g.extensionsUsed.append("KHR_materials_emissive_strength")
    mat = w.material(
        emissiveFactor=[0.5, 0.25, 1.0],
        extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}},
        pbrMetallicRoughness=pygltflib.PbrMetallicRoughness(
            baseColorFactor=[0.2, 0.4, 0.6, 1], metallicFactor=0.5
        ),
    )
    a = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F, material=mat))
    b = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F), translation=[2, 0, 0])  # no material: the spec's default
    scene, _ = _quiet_load(w.save(tmp_path / "e.glb", [a, b]))
    i0, i1 = scene.instances
    assert i0.emission == pytest.approx((2.0, 1.0, 4.0))
    p = i0.material.params
    assert p["kd"] == pytest.approx([0.1, 0.2, 0.3], abs=1e-6)
    assert p["f0"] == pytest.approx([0.12, 0.22, 0.32], abs=1e-6)
    assert p["roughness"] == pytest.approx(1.0)  # roughnessFactor defaults to 1
    q = i1.material.params  # white, metallic 1, roughness 1: no diffuse, F0 = 1
    assert q["kd"] == pytest.approx([0, 0, 0]) and q["f0"] == pytest.approx([1, 1, 1])


def test_double_sided_draws_the_back_and_mask_drops_transparent_primitives(tmp_path: Path) -> None:
    quad_v = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=np.float32)
    quad_f = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)
    back_cam = brdfpy.Camera.perspective((0, 0, -3), (0, 0, 0), fovy=50)
    covered = []
    for double in (False, True):
        w = Writer()
        mat = w.material(doubleSided=double)
        root = w.node(mesh=w.mesh(quad_v, quad_f, material=mat))
        scene, _ = _quiet_load(w.save(tmp_path / f"q{double}.glb", [root]))
        scene.lights = [brdfpy.DirectionalLight((0, 0, 1), intensity=3.0)]  # lights the back
        img = scene.render(back_cam, 64, 64, outputs=("hdr", "depth"))
        covered.append((img.covered_pixels, float(img.hdr.max())))
    assert covered[0][0] == 0  # single-sided: culled from behind
    assert covered[1][0] > 1000 and covered[1][1] > 0.05  # double-sided: drawn and lit
    w = Writer()
    clear = w.material(
        alphaMode="MASK",
        alphaCutoff=0.5,
        pbrMetallicRoughness=pygltflib.PbrMetallicRoughness(baseColorFactor=[1, 1, 1, 0.3]),
    )
    blend = w.material(alphaMode="BLEND")
    a = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F, material=clear))
    b = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F, material=blend))
    scene, _ = _quiet_load(w.save(tmp_path / "alpha.glb", [a, b]))
    assert len(scene.instances) == 1
    notes = " ".join(scene.asset.notes)  # type: ignore[attr-defined]
    assert "MASK" in notes and "BLEND rendered opaque" in notes


# -- lights and cameras -------------------------------------------------------------------------------------


def test_khr_lights_punctual_and_cameras(tmp_path: Path) -> None:
    w = Writer()
    w.lights(
        [
            {"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 20.0, "range": 9.0},
            {"type": "spot", "intensity": 7.0, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
            {"type": "directional", "color": [0.9, 0.9, 1.0], "intensity": 2.0},
        ]
    )
    mesh = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F))
    point = w.node(translation=[0, 3, 0], extensions={"KHR_lights_punctual": {"light": 0}})
    # A spot above, pointing down: the node's -z turned to -y by -90 degrees about x.
    t = math.radians(90) / 2
    spot = w.node(
        translation=[1, 4, 0],
        rotation=[-math.sin(t), 0, 0, math.cos(t)],
        extensions={"KHR_lights_punctual": {"light": 1}},
    )
    sun = w.node(rotation=_quat_y(90), extensions={"KHR_lights_punctual": {"light": 2}})  # -z -> -x
    w.g.cameras = [
        pygltflib.Camera(
            type="perspective",
            perspective=pygltflib.Perspective(yfov=0.7, znear=0.1, zfar=50.0, aspectRatio=1.5),
        ),
        pygltflib.Camera(
            type="orthographic",
            orthographic=pygltflib.Orthographic(xmag=2.0, ymag=1.0, znear=0.01, zfar=20.0),
        ),
    ]
    cam0 = w.node(camera=0, translation=[0, 1, 5])
    cam1 = w.node(camera=1, translation=[5, 0, 0], rotation=_quat_y(90))  # looks along -x
    scene, cams = _quiet_load(w.save(tmp_path / "l.glb", [mesh, point, spot, sun, cam0, cam1]))
    lp, ls, ld = scene.lights
    assert isinstance(lp, brdfpy.PointLight) and lp.position == pytest.approx((0, 3, 0))
    assert lp.emitted == pytest.approx((20.0, 10.0, 5.0))  # candela, colour x intensity
    assert isinstance(ls, brdfpy.SpotLight)
    assert ls.position == pytest.approx((1, 4, 0), abs=1e-6) and ls.direction == pytest.approx(
        (0, -1, 0), abs=1e-6
    )
    f = ls._fields()
    assert f["inner_angle"] == pytest.approx(0.2, rel=1e-5)  # half-angles [rad], as in the file
    assert f["outer_angle"] == pytest.approx(0.6, rel=1e-5)
    assert isinstance(ld, brdfpy.DirectionalLight) and ld.direction == pytest.approx((-1, 0, 0), abs=1e-6)
    assert ld.emitted == pytest.approx((1.8, 1.8, 2.0))  # lux
    asset = scene.asset  # type: ignore[attr-defined]
    assert not asset.default_lights and not asset.default_camera
    assert asset.lights[0]["range"] == 9.0 and any("range 9" in n for n in asset.notes)
    c0, c1 = cams
    assert c0.kind == "perspective" and c0.fovy == pytest.approx(math.degrees(0.7), rel=1e-5)
    assert (
        c0.eye == pytest.approx((0, 1, 5)) and c0.near == pytest.approx(0.1) and c0.far == pytest.approx(50)
    )
    d = np.subtract(c0.target, c0.eye)
    assert d / np.linalg.norm(d) == pytest.approx((0, 0, -1), abs=1e-6)
    assert asset.cameras[0].aspect == pytest.approx(1.5)
    assert c1.kind == "orthographic" and c1.height == pytest.approx(2.0)
    d1 = np.subtract(c1.target, c1.eye)
    assert d1 / np.linalg.norm(d1) == pytest.approx((-1, 0, 0), abs=1e-6)
    assert asset.cameras[1].aspect == pytest.approx(2.0)
    # Both cameras see the wedge.
    for c in cams:
        assert scene.render(c, 48, 32, outputs=("depth",)).covered_pixels > 0


def test_up_turns_meshes_lights_and_cameras_together(tmp_path: Path) -> None:
    w = Writer()
    w.lights([{"type": "point", "intensity": 5.0}])
    mesh = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F))
    light = w.node(translation=[0, 0, 3], extensions={"KHR_lights_punctual": {"light": 0}})
    w.g.cameras = [
        pygltflib.Camera(type="perspective", perspective=pygltflib.Perspective(yfov=0.8, znear=0.1))
    ]
    cam = w.node(camera=0, translation=[0, 0.3, 4])
    path = w.save(tmp_path / "up.glb", [mesh, light, cam])
    s0, c0 = _quiet_load(path)
    s1, c1 = _quiet_load(path, up="z")  # (x, y, z) -> (x, z, -y)
    assert s1.lights[0].position == pytest.approx((0, 3, 0), abs=1e-6)  # type: ignore[attr-defined]
    assert c1[0].eye == pytest.approx((0, 4, -0.3), abs=1e-6)
    np.testing.assert_allclose(s1.instances[0].transform, brdfpy.transforms.up_to_y("z"), atol=1e-12)
    assert c0[0].far > 4  # an infinite zfar: a far plane beyond the scene
    # Everything turned together: the same picture.
    np.testing.assert_allclose(_render(s0, c0[0], 48), _render(s1, c1[0], 48), atol=2e-3)


def test_without_lights_or_cameras_the_defaults_frame_and_light_it(tmp_path: Path) -> None:
    w = Writer()
    root = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F), translation=[10, -3, 2], scale=[4, 4, 4])
    scene, cams = _quiet_load(w.save(tmp_path / "bare.glb", [root]), aspect=1.0)
    asset = scene.asset  # type: ignore[attr-defined]
    assert asset.default_lights and asset.default_camera and len(cams) == 1
    assert len(scene.lights) == 2 and scene.ambient_light == (0.1, 0.1, 0.1)
    img = scene.render(cams[0], 64, 64, outputs=("hdr", "depth"))
    assert img.covered_pixels > 64 * 64 * 0.1  # framed
    assert float(img.hdr[img.mask].mean()) > 0.05  # lit


# -- file variants ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("form", ["glb", "gltf", "datauri"])
def test_gltf_bin_glb_and_data_uri_give_the_same_scene(tmp_path: Path, form: str) -> None:
    w = Writer()
    uv = np.linspace(0, 1, 10, dtype=np.float32).reshape(5, 2)
    colors = np.linspace(0.1, 0.9, 15, dtype=np.float32).reshape(5, 3)
    root = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F, TEXCOORD_0=uv, COLOR_0=colors), translation=[0, 1, 0])
    path = w.save(tmp_path / f"s.{'glb' if form == 'glb' else 'gltf'}", [root], form)
    scene, _ = _quiet_load(path)
    (part,) = scene.asset.parts  # type: ignore[attr-defined]
    mesh = part.instance.mesh
    np.testing.assert_array_equal(mesh.vertices, WEDGE_V)
    np.testing.assert_array_equal(mesh.faces, WEDGE_F)
    np.testing.assert_array_equal(part.uvs, uv)
    np.testing.assert_allclose(mesh.colors, colors)
    assert part.tangents is None
    np.testing.assert_allclose(part.instance.transform, _trs(t=(0, 1, 0)))


def _png_1x1() -> bytes:
    import io

    from PIL import Image

    buf = io.BytesIO()
    Image.new("RGBA", (1, 1), (255, 128, 0, 255)).save(buf, format="PNG")
    return buf.getvalue()


def test_texture_references_are_kept_beside_the_applied_textures(tmp_path: Path) -> None:
    w = Writer()
    png = _png_1x1()
    view = w._view(png)
    w.g.images = [pygltflib.Image(bufferView=view, mimeType="image/png", name="orange")]
    w.g.samplers = [
        pygltflib.Sampler(
            wrapS=pygltflib.CLAMP_TO_EDGE, wrapT=pygltflib.MIRRORED_REPEAT, magFilter=pygltflib.NEAREST
        )
    ]
    w.g.textures = [pygltflib.Texture(source=0, sampler=0)]
    mat = w.material(
        pbrMetallicRoughness=pygltflib.PbrMetallicRoughness(baseColorTexture=pygltflib.TextureInfo(index=0)),
        normalTexture=pygltflib.NormalMaterialTexture(index=0, scale=0.5),
    )
    uv = np.zeros((5, 2), dtype=np.float32)
    root = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F, material=mat, TEXCOORD_0=uv))
    scene, _ = load_scene(w.save(tmp_path / "t.glb", [root]))  # every reference applied: no warning
    m = scene.asset.materials[0]  # type: ignore[attr-defined]
    base, normal = m.textures["baseColorTexture"], m.textures["normalTexture"]
    assert base.image.data == png and base.image.mime_type == "image/png" and base.color_space == "srgb"
    assert (base.wrap_s, base.wrap_t, base.mag_filter) == ("CLAMP_TO_EDGE", "MIRRORED_REPEAT", "NEAREST")
    assert normal.scale == 0.5 and normal.color_space == "linear" and normal.tex_coord == 0
    inst = scene.asset.parts[0].instance  # type: ignore[attr-defined]
    assert isinstance(inst.material, brdfpy.TexturedModel) and set(inst.material.textures) == {"kd", "f0"}
    assert inst.normal_map is not None and inst.normal_scale == 0.5
    assert inst.normal_map.wrap == ("clamp", "mirror") and inst.normal_map.filter == "nearest"


# -- textures applied ----------------------------------------------------------------------------------------

# A unit quad in the z = 0 plane facing +z, with glTF texture coordinates: (0, 0) at its top-left corner
# (-1, 1), v growing downward.
QUAD_V = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=np.float32)
QUAD_F = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)
QUAD_UV = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], dtype=np.float32)
QUAD_N = np.tile(np.array([0, 0, 1], dtype=np.float32), (4, 1))
QUAD_MESH_UV = brdfpy.Mesh(QUAD_V, QUAD_F, QUAD_N, uvs=QUAD_UV)
# Looking down -z at the quad, which fills the frame: pixel row 0 is the quad's top edge.
QUAD_CAM = brdfpy.Camera.orthographic(eye=(0, 0, 3), target=(0, 0, 0), up=(0, 1, 0), height=2.0)


def _png(rgba: np.ndarray) -> bytes:
    import io

    from PIL import Image

    buf = io.BytesIO()
    a = np.asarray(rgba, dtype=np.uint8)
    Image.fromarray(a, {2: "L", 3: {3: "RGB", 4: "RGBA"}.get(a.shape[-1], "L")}[a.ndim]).save(buf, "PNG")
    return buf.getvalue()


def _srgb_decode(c8: Any) -> np.ndarray:
    """IEC 61966-2-1's sRGB decoding of 8-bit values."""
    c = np.asarray(c8, dtype=np.float64) / 255
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def _quad_scene(
    tmp_path: Path,
    name: str,
    images: dict[str, np.ndarray] | None = None,
    texcoord: int = 0,
    **material: Any,
) -> brdfpy.Scene:
    """The quad with a material whose textures are `images` (slot -> 8-bit array; NEAREST sampling),
    lit by one directional light."""
    w = Writer()
    textures: dict[str, Any] = {}
    w.g.samplers = [pygltflib.Sampler(magFilter=pygltflib.NEAREST, minFilter=pygltflib.NEAREST)]
    for slot, img in (images or {}).items():
        w.g.images.append(pygltflib.Image(bufferView=w._view(_png(img)), mimeType="image/png"))
        w.g.textures.append(pygltflib.Texture(source=len(w.g.images) - 1, sampler=0))
        textures[slot] = len(w.g.textures) - 1
    pbr = pygltflib.PbrMetallicRoughness(
        baseColorFactor=material.pop("base", [1, 1, 1, 1]),
        metallicFactor=material.pop("metallic", 0.0),
        roughnessFactor=material.pop("roughness", 1.0),
    )
    if "base" in textures:
        pbr.baseColorTexture = pygltflib.TextureInfo(index=textures["base"], texCoord=texcoord)
    if "mr" in textures:
        pbr.metallicRoughnessTexture = pygltflib.TextureInfo(index=textures["mr"])
    if "emissive" in textures:
        material["emissiveTexture"] = pygltflib.TextureInfo(index=textures["emissive"])
    if "occlusion" in textures:
        material["occlusionTexture"] = pygltflib.OcclusionTextureInfo(
            index=textures["occlusion"], strength=material.pop("strength", 1.0)
        )
    mat = w.material(pbrMetallicRoughness=pbr, **material)
    mesh = w.mesh(QUAD_V, QUAD_F, material=mat, NORMAL=QUAD_N, TEXCOORD_0=QUAD_UV, TEXCOORD_1=QUAD_UV)
    scene, _ = load_scene(w.save(tmp_path / f"{name}.glb", [w.node(mesh=mesh)]), lights="none")
    scene.add_light(brdfpy.DirectionalLight((0.3, -0.2, -1.0), intensity=2.0))
    return scene


def test_gltf_base_color_texture_reads_from_the_top_left_and_decodes_srgb(tmp_path: Path) -> None:
    # 2x2 texels: top row (188, 0, 0) and green, bottom row blue and white; 188 is sRGB-decoded to 0.503.
    img = np.array([[[188, 0, 0, 255], [0, 255, 0, 255]], [[0, 0, 255, 255], [255, 255, 255, 255]]])
    textured = _render(_quad_scene(tmp_path, "tex", {"base": img}), QUAD_CAM, 64)
    for (row, col), texel in zip([(16, 16), (16, 48), (48, 16), (48, 48)], img.reshape(4, 4)):
        factor = [*_srgb_decode(texel[:3]), 1.0]
        plain = _render(_quad_scene(tmp_path, f"c{row}{col}", base=factor), QUAD_CAM, 64)
        np.testing.assert_allclose(textured[row, col], plain[row, col], rtol=1e-5, atol=1e-7)
        assert plain[row, col].max() > 0.05  # lit


def test_gltf_metallic_roughness_texture_packs_roughness_in_g_and_metalness_in_b(tmp_path: Path) -> None:
    base = [0.9, 0.6, 0.3, 1.0]
    mr = np.array([[[7, 100, 200]]])  # R unused, G roughness, B metalness (linear)
    textured_scene = _quad_scene(tmp_path, "mr", {"mr": mr}, base=base, metallic=0.8, roughness=0.9)
    inst = textured_scene.instances[0]
    assert {"kd", "f0", "roughness"} <= set(inst.material.textures)
    plain_scene = _quad_scene(
        tmp_path, "mr_plain", base=base, metallic=0.8 * 200 / 255, roughness=0.9 * 100 / 255
    )
    a, b = _render(textured_scene, QUAD_CAM, 32), _render(plain_scene, QUAD_CAM, 32)
    np.testing.assert_allclose(a, b, rtol=1e-5, atol=1e-7)
    # Swapping G and B changes the image: the channels are not interchangeable.
    swapped_scene = _quad_scene(
        tmp_path, "mr_sw", {"mr": mr[..., [0, 2, 1]]}, base=base, metallic=0.8, roughness=0.9
    )
    swapped = _render(swapped_scene, QUAD_CAM, 32)
    assert np.abs(swapped - a).max() > 1e-3


def test_gltf_emissive_texture_times_its_factor_and_occlusion_with_its_strength(tmp_path: Path) -> None:
    emissive = np.array([[[255, 128, 0]]])
    scene = _quad_scene(tmp_path, "em", {"emissive": emissive}, base=[0, 0, 0, 1], emissiveFactor=[0.5, 1, 1])
    scene.lights.clear()
    hdr = _render(scene, QUAD_CAM, 16)
    np.testing.assert_allclose(hdr[8, 8], [0.5, _srgb_decode(128), 0.0], rtol=1e-5, atol=1e-7)

    def ambient_only(name: str, images: dict[str, np.ndarray] | None, **kw: Any) -> np.ndarray:
        s = _quad_scene(tmp_path, name, images, base=[0.5, 0.5, 0.5, 1], **kw)
        s.lights.clear()
        s.ambient_light = 1.0
        return _render(s, QUAD_CAM, 16)

    occ = np.array([[[64, 0, 0]]])  # R = 64/255, linear
    ratio = ambient_only("occ", {"occlusion": occ}, strength=0.5) / ambient_only("no_occ", None)
    np.testing.assert_allclose(ratio[8, 8], 1 + 0.5 * (64 / 255 - 1), rtol=1e-5)


def test_gltf_mask_cuts_out_texels_below_the_cutoff_and_shows_what_is_behind(tmp_path: Path) -> None:
    # 2x2 texels: alpha 0 in the left column, 200 in the right; factor alpha 0.8 -> 0 and 0.63.
    img = np.array([[[255, 0, 0, 0], [255, 0, 0, 200]], [[255, 0, 0, 0], [255, 0, 0, 200]]])
    scene = _quad_scene(
        tmp_path, "mask", {"base": img}, base=[1, 1, 1, 0.8], alphaMode="MASK", alphaCutoff=0.6
    )
    inst = scene.instances[0]
    assert inst.alpha_mask is not None and inst.alpha_cutoff == pytest.approx(0.6)
    behind = brdfpy.Mesh(QUAD_V - np.float32([0, 0, 1]), QUAD_F, QUAD_N)
    scene.add(behind, brdfpy.model("lambert", kd=(0, 0, 0.8)))
    img_ = scene.render(QUAD_CAM, 32, 32, outputs=("hdr", "triangle_id"))
    left, right = img_.hdr[:, :14], img_.hdr[:, 18:]
    assert (left[..., 2] > 0).all() and (left[..., 0] == 0).all()  # the blue quad behind shows through
    assert (right[..., 0] > 20 * right[..., 2]).all()  # the red texels pass (blue: only the white highlight)
    # Raising the cutoff above 0.63 cuts the right column too.
    inst.alpha_cutoff = 0.7
    assert (scene.render(QUAD_CAM, 32, 32, outputs=("hdr",)).hdr[:, 18:, 0] == 0).all()
    with pytest.raises(TypeError, match=r"alpha_mask: expected tex\.channel"):
        scene.add(QUAD_MESH_UV, "lambert", alpha_mask=brdfpy.Texture(np.ones((2, 2))))


def test_textures_that_cannot_be_applied_warn_and_say_why(tmp_path: Path) -> None:
    img = np.full((1, 1, 3), 200)
    with pytest.warns(TexturesNotAppliedWarning, match="TEXCOORD_1"):
        scene = _quad_scene(tmp_path, "tc1", {"base": img}, texcoord=1)
    assert any("TEXCOORD_1" in n for n in scene.asset.notes)  # type: ignore[attr-defined]
    w = Writer()
    w.g.images = [pygltflib.Image(bufferView=w._view(_png(img)), mimeType="image/png")]
    w.g.textures = [pygltflib.Texture(source=0)]
    mat = w.material(
        pbrMetallicRoughness=pygltflib.PbrMetallicRoughness(baseColorTexture=pygltflib.TextureInfo(index=0))
    )
    path = w.save(tmp_path / "nouv.glb", [w.node(mesh=w.mesh(WEDGE_V, WEDGE_F, material=mat))])
    with pytest.warns(TexturesNotAppliedWarning, match="no texture coordinates"):
        load_scene(path)


def test_mtl_maps_multiply_their_constants_and_a_bump_map_becomes_a_normal_map(tmp_path: Path) -> None:
    from PIL import Image

    Image.fromarray(np.full((2, 2), 128, np.uint8), "L").save(tmp_path / "grey.png")
    ramp = np.round(np.tile(np.arange(8) / 7, (8, 1)) * 255).astype(np.uint8)
    Image.fromarray(ramp, "L").save(tmp_path / "height.png")
    (tmp_path / "m.mtl").write_text(
        "newmtl t\nKd 0.5 0.25 1\nKs 0.2 0.2 0.2\nNs 50\nmap_Kd grey.png\nmap_Bump -bm 2 height.png\n"
    )
    (tmp_path / "q.obj").write_text(
        "mtllib m.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "vn 0 0 1\nusemtl t\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n"
    )
    scene, _ = load_scene(tmp_path / "q.obj")
    inst = scene.instances[0]
    kd = inst.material.textures["kd"]
    np.testing.assert_allclose(kd.mean(), np.array([0.5, 0.25, 1]) * _srgb_decode(128), rtol=1e-6)
    assert inst.normal_map is not None and inst.normal_map.channels == 3
    # The ramp rises by 255/7 per texel (rounded to 8 bits): interior normals tilt toward -x by the
    # central difference times -bm, and not at all in y.
    n = inst.normal_map.levels()[0][4, 1:7] * 2 - 1
    slope = 2 * (ramp[4, 2:8].astype(float) - ramp[4, 0:6]) / 2 / 255
    expect = np.stack([-slope, np.zeros(6), np.ones(6)], -1)
    expect /= np.linalg.norm(expect, axis=-1, keepdims=True)
    np.testing.assert_allclose(n, expect, atol=2e-6)


def test_height_to_normal_map_of_a_ramp_tilts_against_the_rise(tmp_path: Path) -> None:
    from brdfpy.assets import height_to_normal_map

    h = np.tile(np.linspace(0, 1, 16, dtype=np.float32)[:, None], (1, 16))  # rises down the image
    nm = height_to_normal_map(brdfpy.Texture(h, wrap="clamp", filter="bilinear"), strength=3.0)
    n = nm.levels()[0][5:10, 5:10] * 2 - 1
    # Rising downward = falling toward +y (up the image): the normal tilts toward +y.
    expect = np.array([0.0, 3.0 / 15, 1.0]) / np.linalg.norm([0.0, 3.0 / 15, 1.0])
    np.testing.assert_allclose(n, np.broadcast_to(expect, n.shape), atol=2e-6)
    assert nm.wrap == "clamp" and nm.filter == "bilinear"


def test_texture_sources_and_encoded_images_refuse_bad_input() -> None:
    t = brdfpy.Texture(np.full((2, 2, 3), 0.5, np.float32))
    with pytest.raises(ValueError, match="texture: expected a finite factor"):
        brdfpy.TextureSource.scaled(t, -1.0)
    with pytest.raises(TypeError, match=r"texture: expected a brdfpy\.Texture"):
        brdfpy.TextureSource.squared(0.5)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="base_color: expected a texture, a scaled texture or a constant"):
        brdfpy.TextureSource.metallic_f0(brdfpy.TextureSource.squared(t), 0.5)
    with pytest.raises(ValueError, match="metallic_roughness_texture: needs G"):
        brdfpy.assets.metallic_roughness(
            (1, 1, 1), 1, 1, metallic_roughness_texture=brdfpy.Texture(np.ones((2, 2)))
        )
    with pytest.raises(TypeError, match="data: expected the bytes"):
        brdfpy.Texture.from_bytes("x.png")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="data: not an image"):
        brdfpy.Texture.from_bytes(b"not a png")
    with pytest.raises(TypeError, match="wrap: expected one of"):
        brdfpy.Texture(np.ones((2, 2)), wrap=("repeat",))  # type: ignore[arg-type]
    m = brdfpy.model("cook_torrance", roughness=brdfpy.TextureSource.squared(t.channel(1), 0.5))
    assert m.params["roughness"] == pytest.approx(0.0625)  # the mean's square: (0.5 * 0.5)^2
    assert "TextureSource.squared" in repr(m)


# -- OBJ + MTL, STL -----------------------------------------------------------------------------------------


def test_obj_with_mtl_maps_its_materials(tmp_path: Path) -> None:
    (tmp_path / "m.mtl").write_text(
        "newmtl shiny\nKa 0.1 0.1 0.1\nKd 0.8 0.2 0.1\nKs 0.5 0.5 0.5\nNs 120\nd 0.5\nKe 0 0 0.5\n"
        "map_Kd -s 2 2 1 wood.png\nmap_Bump -bm 0.3 bump.png\nillum 2\n"
        "newmtl matte\nKd 0.3 0.6 0.3\nillum 1\nnorm n.png\n"
        "newmtl pbr\nKd 0.9 0.9 0.9\nPr 0.4\nPm 1\n"
    )
    (tmp_path / "a.obj").write_text(
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\n"
        "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvt 0.5 0.5\n"
        "usemtl shiny\nf 1/1 2/2 3/3\nusemtl matte\nf 2/2 4/4 3/3\n"
        "usemtl pbr\nf 1/1 2/2 5/5\nusemtl nowhere\nf 1 3 5\n"
    )
    # wood.png has -s (not applied), bump.png and n.png are missing: three references not applied.
    with pytest.warns(TexturesNotAppliedWarning, match="3 texture reference"):
        scene, _ = load_scene(tmp_path / "a.obj")
    asset = scene.asset  # type: ignore[attr-defined]
    names = [p.name for p in asset.parts]
    assert names == ["shiny", "matte", "pbr", "default"]
    shiny, matte, pbr, default = (p.instance for p in asset.parts)
    assert shiny.material.name == "blinn_phong"
    sp = shiny.material.params
    assert sp["kd"] == pytest.approx([0.8, 0.2, 0.1]) and sp["ks"] == pytest.approx([0.5] * 3)
    assert sp["shininess"] == pytest.approx(120)  # Ns is the exponent of (n.h)^Ns
    assert shiny.ambient == pytest.approx((0.1, 0.1, 0.1)) and shiny.emission == pytest.approx((0, 0, 0.5))
    assert matte.material.params["ks"] == pytest.approx([0, 0, 0])  # illum 1: no highlight
    assert pbr.material.name == "cook_torrance" and pbr.material.params["f0"] == pytest.approx([0.9] * 3)
    assert pbr.material.params["roughness"] == pytest.approx(0.16)
    assert default.material.params["kd"] == pytest.approx([0.8] * 3)
    m0 = asset.materials[0]
    assert m0.opacity == 0.5 and any("d = 0.5" in n for n in asset.notes)
    assert m0.textures["map_Kd"].uv_scale == (2.0, 2.0)
    assert m0.textures["map_Kd"].image.path == str(tmp_path / "wood.png")
    assert m0.textures["map_Bump"].scale == pytest.approx(0.3)
    assert "norm" in asset.materials[1].textures
    assert any("nowhere" in s for s in asset.skipped)
    np.testing.assert_allclose(asset.parts[0].uvs, [[0, 1], [1, 1], [0, 0]])  # vt flipped to glTF's origin
    assert asset.default_camera and asset.default_lights


def test_obj_whose_mtl_is_missing_or_broken(tmp_path: Path) -> None:
    (tmp_path / "a.obj").write_text("mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n")
    scene, _ = load_scene(tmp_path / "a.obj")
    assert any("gone.mtl" in s for s in scene.asset.skipped)  # type: ignore[attr-defined]
    (tmp_path / "gone.mtl").write_text("newmtl x\nKd -1 0 0\n")
    with pytest.raises(brdfpy.BrdfError, match=r"gone\.mtl.*newmtl x: Kd"):
        load_scene(tmp_path / "a.obj")


TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def _stl_ascii(v: np.ndarray, f: np.ndarray) -> str:
    lines = ["solid tet"]
    for tri in f:
        lines += ["facet normal 0 0 0", "outer loop"]
        lines += [f"vertex {x:.6f} {y:.6f} {z:.6f}" for x, y, z in v[tri]]
        lines += ["endloop", "endfacet"]
    return "\n".join([*lines, "endsolid tet\n"])


def _stl_binary(v: np.ndarray, f: np.ndarray) -> bytes:
    out = b"\0" * 80 + struct.pack("<I", len(f))
    for tri in f:
        out += struct.pack("<3f", 0, 0, 0) + v[tri].astype("<f4").tobytes() + b"\0\0"
    return out


@pytest.mark.parametrize("kind", ["ascii", "binary"])
def test_stl_is_one_mesh_with_the_default_material(tmp_path: Path, kind: str) -> None:
    p = tmp_path / f"tet_{kind}.stl"
    if kind == "ascii":
        p.write_text(_stl_ascii(TET_V, TET_F))
    else:
        p.write_bytes(_stl_binary(TET_V, TET_F))
    scene, cams = load_scene(p, up="z")
    (inst,) = scene.instances
    assert inst.mesh.n_faces == 4 and inst.mesh.n_vertices == 4  # welded corners
    assert sorted(map(tuple, inst.mesh.vertices.tolist())) == sorted(map(tuple, TET_V.tolist()))
    assert inst.material.params["kd"] == pytest.approx([0.8] * 3)  # DEFAULT_MATERIAL
    np.testing.assert_allclose(inst.transform, brdfpy.transforms.up_to_y("z"))
    assert scene.render(cams[0], 48, 48, outputs=("depth",)).covered_pixels > 100


# -- malformed files ----------------------------------------------------------------------------------------


def _simple(tmp_path: Path, form: str = "glb", name: str = "s") -> Path:
    w = Writer()
    root = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F))
    return w.save(tmp_path / f"{name}.{'glb' if form == 'glb' else 'gltf'}", [root], form)


def test_truncated_glb(tmp_path: Path) -> None:
    p = _simple(tmp_path)
    data = p.read_bytes()
    for cut in (8, 40, len(data) - 20):
        q = tmp_path / f"cut{cut}.glb"
        q.write_bytes(data[:cut])
        with pytest.raises(brdfpy.BrdfError, match=rf"cut{cut}\.glb.*(GLB|buffers\[0\])"):
            load_scene(q)


def test_accessor_past_its_buffer_view(tmp_path: Path) -> None:
    w = Writer()
    root = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F))
    w.g.accessors[0].count = 500  # POSITION claims 500 vertices in a view of 5
    p = w.save(tmp_path / "acc.glb", [root])
    with pytest.raises(brdfpy.BrdfError, match=r"acc\.glb.*POSITION.*accessors\[0\].*past"):
        load_scene(p)


def test_missing_bin_and_missing_image(tmp_path: Path) -> None:
    p = _simple(tmp_path, "gltf", "nobin")
    p.with_suffix(".bin").unlink()
    with pytest.raises(brdfpy.BrdfError, match=r"nobin\.gltf.*buffers\[0\].*nobin\.bin"):
        load_scene(p)
    w = Writer()
    w.g.images = [pygltflib.Image(uri="missing.png")]
    w.g.textures = [pygltflib.Texture(source=0)]
    root = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F))
    q = w.save(tmp_path / "noimg.gltf", [root], "gltf")
    with pytest.raises(brdfpy.BrdfError, match=r"noimg\.gltf.*images\[0\].*missing\.png"):
        load_scene(q)


def test_unsupported_required_extension(tmp_path: Path) -> None:
    w = Writer()
    root = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F))
    w.g.extensionsUsed = ["KHR_draco_mesh_compression"]
    w.g.extensionsRequired = ["KHR_draco_mesh_compression"]
    p = w.save(tmp_path / "draco.glb", [root])
    with pytest.raises(brdfpy.BrdfError, match=r"draco\.glb.*extensionsRequired.*KHR_draco_mesh_compression"):
        load_scene(p)


def test_bad_arguments(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="path: no such file"):
        load_scene(tmp_path / "none.glb")
    (tmp_path / "x.fbx").write_bytes(b"x")
    with pytest.raises(ValueError, match=r"path: unsupported scene file type '\.fbx'"):
        load_scene(tmp_path / "x.fbx")
    with pytest.raises(ValueError, match="lights: expected"):
        load_scene(_simple(tmp_path), lights="some")
    with pytest.raises(ValueError, match="up: expected"):
        load_scene(_simple(tmp_path), up="w")


# -- the command line ---------------------------------------------------------------------------------------


def test_cli_renders_a_gltf_scene_through_its_camera(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from brdfpy.cli import main

    w = Writer()
    mat = w.material(
        pbrMetallicRoughness=pygltflib.PbrMetallicRoughness(
            baseColorFactor=[0.9, 0.3, 0.1, 1], metallicFactor=0.0, roughnessFactor=0.4
        )
    )
    root = w.node(mesh=w.mesh(WEDGE_V, WEDGE_F, material=mat))
    w.g.cameras = [
        pygltflib.Camera(
            type="perspective", perspective=pygltflib.Perspective(yfov=0.6, znear=0.1, aspectRatio=2.0)
        )
    ]
    cam = w.node(camera=0, translation=[0.3, 0.4, 4])
    p = w.save(tmp_path / "cli.glb", [root, cam])
    out = tmp_path / "cli.png"
    assert main(["render", "--scene", str(p), "-o", str(out), "--samples", "1"]) == 0
    from PIL import Image

    with Image.open(out) as im:
        assert im.size == (1280, 640)  # the camera's aspect ratio 2
        px = np.asarray(im.convert("RGB"))
    assert (px.reshape(-1, 3).max(axis=1) > 40).mean() > 0.01
    text = capsys.readouterr().out
    assert "no lights in the file" in text and "camera 0 of 1" in text
    out2 = tmp_path / "turned.png"
    assert (
        main(
            [
                "render",
                "--scene",
                str(p),
                "-o",
                str(out2),
                "--size",
                "64x48",
                "--up",
                "z",
                "--rotate",
                "30",
                "-q",
            ]
        )
        == 0
    )
    assert out2.exists()
    assert main(["render", "--scene", str(p), "--camera", "3", "-o", str(out2)]) == 2
    assert "--camera: the file has 1 camera(s)" in capsys.readouterr().err
