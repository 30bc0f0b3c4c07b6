"""Everything a user sends to another process pickles with the same bits: models (every registry model,
non-default parameters, every choice), measured tables, meshes (normals, colours, obscurance), cameras,
lights, scenes and images. "Same" is checked on what the objects compute — evaluations and renders
compared bit for bit — not only on their attributes.

Why bit for bit is not automatic: the public constructors normalise what they are given (mesh normals,
light directions) and the camera takes degrees; rebuilding from the stored values through them moves
the last bit of about a third of a mesh's normals. The last tests show that this would happen.
"""

from __future__ import annotations

import pickle
import subprocess
import sys
import zlib
from typing import Any

import brdfpy
import numpy as np
import pytest
from brdfpy import measured
from brdfpy import transforms as tf

RNG_SEED = 20240613
PROTOCOLS = sorted({2, pickle.DEFAULT_PROTOCOL, pickle.HIGHEST_PROTOCOL})


def roundtrip(obj: Any, protocol: int = pickle.HIGHEST_PROTOCOL) -> Any:
    return pickle.loads(pickle.dumps(obj, protocol=protocol))


def roundtrip_out_of_band(obj: Any) -> tuple[Any, int, int]:
    """Pickle as Dask does (protocol 5, large buffers out of band): the copy, the in-band size and the
    bytes of the out-of-band buffers."""
    buffers: list[pickle.PickleBuffer] = []
    data = pickle.dumps(obj, protocol=5, buffer_callback=buffers.append)
    raw = [b.raw() for b in buffers]
    return pickle.loads(data, buffers=raw), len(data), sum(r.nbytes for r in raw)


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


# -- models --------------------------------------------------------------------------------------------


def _directions(k: int = 4000) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(RNG_SEED)
    n = rng.normal(size=(k, 3))
    l = rng.normal(size=(k, 3))
    v = rng.normal(size=(k, 3))
    # Mostly above the surface, some below (the zero branches must match too).
    l += 1.2 * n / np.linalg.norm(n, axis=1, keepdims=True)
    v += 1.2 * n / np.linalg.norm(n, axis=1, keepdims=True)
    t = rng.normal(size=(k, 3))
    return l, v, n, t


def _param_sets(name: str) -> list[dict[str, Any]]:
    """Parameter sets of model ``name`` away from the defaults: every choice of every choice parameter
    appears in some set, bools flipped, scalars and colours drawn inside their documented ranges."""
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    params = brdfpy.model_info(name)["params"]
    n_sets = max([3] + [len(p["choices"] or ()) for p in params])
    sets: list[dict[str, Any]] = []
    for i in range(n_sets):
        s: dict[str, Any] = {}
        for p in params:
            lo, hi = p["min"], p["max"]
            if p["kind"] == "choice":
                choices = p["choices"]
                assert choices is not None
                s[p["name"]] = choices[i % len(choices)]
            elif p["kind"] == "bool":
                s[p["name"]] = bool(i % 2) != bool(p["default"])
            elif p["kind"] == "array":
                s[p["name"]] = [[-0.8, -0.7, 0.9, 12.5 + i], [0.3, 0.2, 0.6, 3.25]]
            else:
                assert lo is not None and hi is not None
                span = min(hi, lo + 3.0) - lo  # huge ranges (shininess 1e4): stay where it looks sane
                u = rng.uniform(0.1, 0.9, size=3 if p["kind"] == "color" else None)
                val = lo + u * span
                s[p["name"]] = tuple(float(x) for x in val) if p["kind"] == "color" else float(val)
        sets.append(s)
    return sets


MODEL_CASES = [(name, i, s) for name in brdfpy.models() for i, s in enumerate(_param_sets(name))]


@pytest.mark.parametrize(
    ("name", "params"), [(n, s) for n, _, s in MODEL_CASES], ids=[f"{n}-{i}" for n, i, _ in MODEL_CASES]
)
def test_every_registry_model_evaluates_the_same_bits_after_a_round_trip(name: str, params: dict) -> None:
    m = brdfpy.model(name, **params)
    l, v, n, t = _directions()
    tangent = t if m.anisotropic else None
    for protocol in PROTOCOLS:
        m2 = roundtrip(m, protocol)
        assert type(m2) is brdfpy.Model
        assert m2.name == m.name and m2.params == m.params
        assert same_bits(m.eval(l, v, n, tangent), m2.eval(l, v, n, tangent))
        assert same_bits(m.shade(l, v, n, tangent), m2.shade(l, v, n, tangent))
    # The sampler is rebuilt too (it is derived from the parameters).
    ts = t[:64] if m.anisotropic else None
    s1 = m.sample(v[:64], n[:64], seed=3, tangent=ts)
    s2 = roundtrip(m).sample(v[:64], n[:64], seed=3, tangent=ts)
    for a, b in zip(s1, s2):
        assert same_bits(a, b)


def test_the_parameter_sets_leave_the_defaults() -> None:
    # Otherwise the test above would compare default models only.
    for name in brdfpy.models():
        defaults = brdfpy.model(name).params
        for s in _param_sets(name):
            assert brdfpy.model(name, **s).params != defaults, name


def _table(res: tuple[int, int, int] = (12, 10, 20)) -> measured.Tabulated:
    return measured.Tabulated.from_model(brdfpy.model("cook_torrance", roughness=0.21, kd=0.3), res)


def test_a_tabulated_brdf_and_its_model_round_trip_with_the_same_values_and_evaluations() -> None:
    t = _table()
    l, v, n, _ = _directions()
    t2 = roundtrip(t)
    assert isinstance(t2, measured.Tabulated) and t2.shape == t.shape
    assert same_bits(t.table, t2.table)
    assert same_bits(t.eval(l, v, n), t2.eval(l, v, n))
    m = t.as_model()
    m2 = roundtrip(m)
    assert m2.name == "measured"
    assert same_bits(m.eval(l, v, n), m2.eval(l, v, n))
    assert same_bits(m.shade(l, v, n), m2.shade(l, v, n))


def test_a_merl_table_read_from_bytes_round_trips() -> None:
    data = _table((8, 8, 16)).to_merl_bytes()
    t = measured.Tabulated.from_merl_bytes(data)
    assert roundtrip(t).to_merl_bytes() == data


def test_an_anisotropic_table_an_rgl_material_and_their_models_round_trip_with_the_same_bits() -> None:
    ward = brdfpy.model("ward", alpha_x=0.2, alpha_y=0.5)
    values = measured.AnisotropicTabulated.from_model(ward, (4, 4, 8, 8)).values
    valid = np.ones(values.shape[:4], bool)
    valid[1, 2, 3] = False
    t = measured.AnisotropicTabulated(values, valid, half_data=True)
    rgl = measured.RglBsdf.from_model(ward, n_theta_i=4, n_phi_i=5, grid=(8, 8))
    l, v, n, tangent = _directions()
    t2 = roundtrip(t)
    assert same_bits(t.values, t2.values) and same_bits(t.valid, t2.valid) and t2.half_data
    assert same_bits(t.eval(l, v, n, tangent), t2.eval(l, v, n, tangent))
    for m in (t.as_model(), rgl.as_model()):
        m2 = roundtrip(m)
        assert m2.name == m.name
        assert same_bits(m.eval(l, v, n, tangent), m2.eval(l, v, n, tangent))
        assert same_bits(m.shade(l, v, n, tangent), m2.shade(l, v, n, tangent))
    assert roundtrip(rgl).to_bytes() == rgl.to_bytes()


# -- meshes, cameras, lights -----------------------------------------------------------------------------


def _mesh_with_everything() -> brdfpy.Mesh:
    m = brdfpy.load_mesh(brdfpy_data("garland_cow.obj"))  # normals computed on load (angle weighting)
    rng = np.random.default_rng(RNG_SEED)
    m = brdfpy.Mesh(m.vertices, m.faces, m.normals, colors=rng.uniform(0, 1, size=(m.n_vertices, 3)))
    m.compute_obscurance(samples=8, store=True)
    return m


def brdfpy_data(name: str) -> str:
    from pathlib import Path

    return str(Path(__file__).parent / "data" / name)


def test_a_mesh_round_trips_with_its_normals_colours_and_obscurance_bit_for_bit() -> None:
    m = _mesh_with_everything()
    for protocol in PROTOCOLS:
        m2 = roundtrip(m, protocol)
        assert isinstance(m2, brdfpy.Mesh)
        for attr in ("vertices", "faces", "normals", "colors", "obscurance"):
            assert same_bits(getattr(m, attr), getattr(m2, attr)), attr
    # A round trip does not tie the copy to the original.
    m2 = roundtrip(m)
    m2.flip_winding()
    assert not same_bits(m.normals, m2.normals)
    assert m.obscurance is not None


def test_a_mesh_without_colours_or_obscurance_round_trips_without_them() -> None:
    m2 = roundtrip(brdfpy.icosphere(2))
    assert m2.colors is None and m2.obscurance is None
    assert same_bits(m2.normals, brdfpy.icosphere(2).normals)


def test_a_mesh_travels_out_of_band_under_protocol_5() -> None:
    # What Dask does: the arrays go as separate buffers (no copy into the pickle stream).
    m = _mesh_with_everything()
    m2, in_band, out_of_band = roundtrip_out_of_band(m)
    assert same_bits(m.normals, m2.normals)
    arrays = m.vertices.nbytes + m.faces.nbytes + m.normals.nbytes + m.colors.nbytes + m.obscurance.nbytes
    assert out_of_band == arrays
    assert in_band < 1000


CAMERAS = [
    brdfpy.Camera.perspective((0.31, 0.77, 2.9), (0.01, 0.1, -0.03), (0.1, 1, 0.05), fovy=37.3, near=0.7),
    brdfpy.Camera.orthographic((2.1, 1.3, 2.2), (0.0, 0.05, 0.0), height=2.71, far=17.0),
    brdfpy.Camera.framing((0.1, 0.2, 0.3), 1.3, direction=(1, 0.4, 2), aspect=4 / 3),
]


@pytest.mark.parametrize("cam", CAMERAS, ids=["perspective", "orthographic", "framing"])
def test_a_camera_round_trips_with_the_same_matrices(cam: brdfpy.Camera) -> None:
    c2 = roundtrip(cam)
    assert isinstance(c2, brdfpy.Camera) and c2.kind == cam.kind
    for attr in ("eye", "target", "up", "near", "far", "fovy", "height"):
        assert getattr(c2, attr) == getattr(cam, attr), attr
    assert same_bits(cam.view_matrix(), c2.view_matrix())
    assert same_bits(cam.projection_matrix(1.37), c2.projection_matrix(1.37))


LIGHTS = [
    brdfpy.DirectionalLight((-0.3, -1.1, -0.7), color=(0.9, 0.8, 0.7)),
    brdfpy.PointLight((1.3, 2.1, 1.7), intensity=(5, 4, 3)),
    brdfpy.PointLight((1.3, 2.1, 1.7), intensity=2, attenuation=(1, 0.2, 0.05)),
    brdfpy.PointLight((0.5, 1, 2), intensity=0.7, attenuation="none"),
    brdfpy.SpotLight((0.2, 2.7, 1.1), (-0.1, -1.0, -0.4), intensity=9, inner_angle=11.1, outer_angle=23.7),
    brdfpy.SpotLight((1, 1, 1), (-1, -1, -1.3), intensity=3, inner_angle=0, outer_angle=5, attenuation=None),
]


@pytest.mark.parametrize("light", LIGHTS, ids=lambda x: type(x).__name__)
def test_a_light_round_trips_with_the_same_fields_and_incident_light(light: brdfpy.Light) -> None:
    l2 = roundtrip(light)
    assert type(l2) is type(light)
    assert l2._fields() == light._fields()
    rng = np.random.default_rng(RNG_SEED)
    for p in rng.normal(size=(50, 3)):
        assert l2.incident(p) == light.incident(p)


# -- scenes and images -----------------------------------------------------------------------------------


def _scene() -> brdfpy.Scene:
    scene = brdfpy.Scene(ambient_light=(0.3, 0.25, 0.2), background=(0.02, 0.03, 0.05))
    cow = _mesh_with_everything()
    scene.add(
        cow,
        brdfpy.model("cook_torrance", roughness=0.27, kd=(0.6, 0.2, 0.1), distribution="beckmann"),
        tf.translate(0, 0.2, 0) @ tf.rotate((0, 1, 0), 31) @ tf.scale(1.7),
        ambient=0.04,
    )
    scene.add(brdfpy.plane(3, 4), _table().as_model(), tf.translate(0, -0.35, 0), ambient=0.1)
    scene.add(
        brdfpy.icosphere(3),
        brdfpy.model("ward", alpha_x=0.1, alpha_y=0.4),
        tf.translate(0.9, 0.1, -0.5) @ tf.scale(0.3),
        emission=(0.05, 0.0, 0.0),
    )
    for light in LIGHTS[:3] + LIGHTS[4:5]:
        scene.add_light(light)
    return scene


RENDERS: list[dict[str, Any]] = [
    {"shading": "phong", "ao": {"stored": True, "samples": 8}, "shadows": True},
    {"shading": "gouraud", "samples": 4, "tonemap": "reinhard_extended", "white": 2.5, "exposure": 0.5},
    {"shading": "flat", "ao": {"samples": 4, "per_pixel": True}},
]


def _render(scene: brdfpy.Scene, cam: brdfpy.Camera, **options: Any) -> brdfpy.Image:
    return scene.render(cam, 96, 72, **options)


def _buffers(img: brdfpy.Image) -> dict[str, np.ndarray]:
    names = getattr(img, "outputs", ("rgb", "hdr", "depth", "normal", "triangle_id"))
    return {name: np.asarray(getattr(img, name)) for name in names}


def test_a_scene_round_trips_and_renders_the_same_image() -> None:
    scene = _scene()
    s2 = roundtrip(scene)
    assert isinstance(s2, brdfpy.Scene)
    assert s2.ambient_light == scene.ambient_light and s2.background == scene.background
    assert len(s2.instances) == 3 and len(s2.lights) == 4
    for a, b in zip(scene.instances, s2.instances):
        assert same_bits(np.asarray(a.transform), np.asarray(b.transform))
        assert (a.ambient, a.emission) == (b.ambient, b.emission)
        assert a.material.name == b.material.name
    cam = CAMERAS[0]
    for opts in RENDERS:
        full = dict(opts, outputs="all") if _has_outputs() else opts
        a, b = _buffers(_render(scene, cam, **full)), _buffers(_render(s2, roundtrip(cam), **full))
        assert a.keys() == b.keys()
        for name in a:
            assert same_bits(a[name], b[name]), (opts, name)
        assert (a["rgb"] > 0).any()


def _has_outputs() -> bool:
    import inspect

    return "outputs" in inspect.signature(brdfpy.Scene.render).parameters


def test_an_image_round_trips_with_every_buffer_and_its_tone_map() -> None:
    opts: dict[str, Any] = {"tonemap": "reinhard_extended", "white": 2.5, "exposure": 0.5}
    if _has_outputs():
        opts["outputs"] = "all"
    img = _render(_scene(), CAMERAS[1], **opts)
    before = _buffers(img)  # reading fills the image's cache, which is not what gets pickled
    img2 = roundtrip(img)
    assert isinstance(img2, brdfpy.Image) and img2.shape == img.shape
    after = _buffers(img2)
    for name in before:
        assert same_bits(before[name], after[name]), name
    assert same_bits(img.tonemapped("aces", -1.0), img2.tonemapped("aces", -1.0))
    assert img2.covered_pixels == img.covered_pixels
    assert repr(img2) == repr(img)


def test_an_image_from_another_process_has_the_bits_of_a_local_render() -> None:
    # A fresh interpreter (no state shared with this one) renders the unpickled scene and sends the image
    # back: what a Dask worker process does.
    scene, cam = _scene(), CAMERAS[2]
    code = (
        "import pickle, sys\n"
        "scene, cam, opts = pickle.load(sys.stdin.buffer)\n"
        "img = scene.render(cam, 96, 72, **opts)\n"
        "sys.stdout.buffer.write(pickle.dumps(img, protocol=5))\n"
    )
    opts = RENDERS[0]
    out = subprocess.run(
        [sys.executable, "-c", code],
        input=pickle.dumps((scene, cam, opts), protocol=5),
        capture_output=True,
        check=True,
        timeout=120,
    ).stdout
    remote = _buffers(pickle.loads(out))
    local = _buffers(_render(scene, cam, **opts))
    for name in local:
        assert same_bits(local[name], remote[name]), name


# -- why the stored values are used ------------------------------------------------------------------------


def test_rebuilding_through_the_public_constructors_would_not_keep_the_bits() -> None:
    # The reason for the raw rebuild functions: normalising already-normalised float32 vectors again moves
    # the last bit of many of them (if this ever stops being true, the raw path is still correct).
    m = brdfpy.load_mesh(brdfpy_data("garland_cow.obj"))
    again = brdfpy.Mesh(m.vertices, m.faces, m.normals)
    assert (again.normals != m.normals).any()
    rng = np.random.default_rng(RNG_SEED)
    moved = 0
    for d in rng.normal(size=(200, 3)):
        stored = brdfpy.DirectionalLight(d).direction
        moved += brdfpy.DirectionalLight(stored).direction != stored
    assert moved > 0


def test_corrupt_pickled_state_is_refused_naming_the_field() -> None:
    from brdfpy import _brdfpy

    m = brdfpy.icosphere(1)
    with pytest.raises(ValueError, match="normals: row 0 is neither a unit vector nor zero"):
        _brdfpy._mesh_from_parts(m.vertices, m.faces, 2 * m.normals, None)
    with pytest.raises(ValueError, match="face 0 indexes vertex 1000"):
        _brdfpy._mesh_from_parts(m.vertices, m.faces + 1000, m.normals, None)
    light = brdfpy.DirectionalLight()
    with pytest.raises(ValueError, match="direction: expected a stored unit vector"):
        _brdfpy._light_with_direction(light._l, [0.0, 0.0, 2.0])
    with pytest.raises(ValueError, match="direction: a point light has no direction"):
        _brdfpy._light_with_direction(brdfpy.PointLight((0, 1, 0))._l, [0.0, 0.0, 1.0])
    state = list(_brdfpy._frame_state(_render(_scene(), CAMERAS[0])._f))
    state[3] = state[3][:-1]  # depth one value short
    with pytest.raises(ValueError, match="depth: expected 0 or 6912 values"):
        _brdfpy._frame_from_state(*state)


def test_buffers_that_arrive_unaligned_are_accepted() -> None:
    # A Dask worker receives an object's arrays as slices of network frames, at any byte offset: the
    # rebuilt objects (and evaluations on such arrays) must not refuse them.
    def shifted(raw: memoryview) -> memoryview:
        buf = bytearray(raw.nbytes + 1)
        buf[1:] = raw.cast("B")
        return memoryview(buf)[1:]

    scene, cam = _scene(), CAMERAS[0]
    img = _render(scene, cam)
    for obj in (scene, img, _table()):
        buffers: list[pickle.PickleBuffer] = []
        data = pickle.dumps(obj, protocol=5, buffer_callback=buffers.append)
        copy = pickle.loads(data, buffers=[shifted(b.raw()) for b in buffers])
        if isinstance(obj, brdfpy.Scene):
            assert same_bits(_render(copy, cam).rgb, img.rgb)
        elif isinstance(obj, brdfpy.Image):
            assert same_bits(copy.rgb, img.rgb)
        else:
            assert same_bits(copy.table, obj.table)
    l, v, n, _ = _directions(100)
    raw = shifted(memoryview(np.ascontiguousarray(l, dtype=np.float32)).cast("B"))
    l_unaligned = np.frombuffer(raw, dtype=np.float32).reshape(100, 3)
    assert not l_unaligned.flags.aligned
    m = brdfpy.model("cook_torrance")
    assert same_bits(m.eval(l_unaligned, v, n), m.eval(l.astype(np.float32), v, n))
