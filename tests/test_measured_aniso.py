"""Anisotropic (4-D) measured tables: the MIT CSAIL ``.dat`` format read from files built here from the
published layout (BRDF Explorer, ``BRDFMeasuredAniso.cpp``: 16 int32, then float32 channel-planar, φ_in
fastest), the writer, bad files, the look-up against its models, reciprocity, rendering, pickling, fitting;
and ``RglBsdf`` as a model."""

from __future__ import annotations

import pickle
import struct
from pathlib import Path

import brdfpy
import numpy as np
import pytest
from brdfpy import measured
from brdfpy.measured import AnisotropicTabulated

HALF_PI, TAU = np.pi / 2, 2 * np.pi


def _dat(dims: tuple[int, int, int, int], values: np.ndarray, half: int = 0, reserved: int = 0) -> bytes:
    """A ``.dat`` file by hand: ``values`` of shape ``dims + (3,)``, written channel by channel."""
    header = [*dims, reserved, reserved, 1, 0, reserved, half, 3, reserved, 0, 0, 0, 0]
    body = np.ascontiguousarray(np.moveaxis(values.astype("<f4"), -1, 0)).tobytes()
    return struct.pack("<16i", *header) + body


def _direction(theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """The unit vector at polar angle ``theta`` and azimuth ``phi`` about +z (x = tangent)."""
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1)


def _explorer_bins(l: np.ndarray, v: np.ndarray, dims: tuple[int, int, int, int]) -> np.ndarray:
    """The bins the BRDF Explorer's shader (``measuredAniso.func``) reads for local ``l``, ``v`` (n = z,
    t = x, b = y): θ by acos, φ = atan2(−w·b, −w·t), indices truncated and clamped."""
    ti, to = np.arccos(np.clip(l[..., 2], 0, 1)), np.arccos(np.clip(v[..., 2], 0, 1))
    pi = np.arctan2(-l[..., 1], -l[..., 0])
    po = np.arctan2(-v[..., 1], -v[..., 0])
    pd = po - pi
    pd = np.where(pd < 0, pd + TAU, pd)
    pi = np.where(pi < 0, pi + TAU, pi)
    n0, n1, n2, n3 = dims
    return np.stack(
        [
            np.clip((ti * n0 / HALF_PI).astype(int), 0, n0 - 1),
            np.clip((to * n1 / HALF_PI).astype(int), 0, n1 - 1),
            np.clip((pd * n2 / TAU).astype(int), 0, n2 - 1),
            np.clip((pi * n3 / TAU).astype(int), 0, n3 - 1),
        ],
        -1,
    )


def _pairs(rng: np.random.Generator, count: int, max_deg: float = 75.0) -> tuple[np.ndarray, np.ndarray]:
    c = np.cos(np.radians(max_deg))
    z = rng.uniform(c, 1.0, (2, count))
    phi = rng.uniform(0, TAU, (2, count))
    s = np.sqrt(1 - z**2)
    d = np.stack([s * np.cos(phi), s * np.sin(phi), z], -1).astype(np.float32)
    return d[0], d[1]


def _rel_rms(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(np.sum((a.astype(np.float64) - b) ** 2) / np.sum(b.astype(np.float64) ** 2)))


WARD = {"alpha_x": 0.25, "alpha_y": 0.5, "kd": 0.2, "ks": 0.3}


def test_a_file_built_from_the_published_layout_reads_to_its_values_at_its_directions() -> None:
    dims = (3, 4, 6, 8)
    rng = np.random.default_rng(1)
    values = rng.uniform(0.0, 2.0, (*dims, 3)).astype(np.float32)
    values[1, 2, 3, 4, 1] = -1.0  # no measurement (one channel is enough)
    data = _dat(dims, values, reserved=99)
    t = AnisotropicTabulated.from_bytes(data)
    assert t.dims == dims and not t.half_data
    want = np.where((values < 0).any(-1, keepdims=True), 0.0, values)
    assert np.array_equal(t.values, want)
    assert not t.valid[1, 2, 3, 4] and t.valid.sum() == np.prod(dims) - 1
    assert t.coverage == pytest.approx(1 - 1 / np.prod(dims))
    # At each bin centre (the Explorer's convention: φ is the azimuth of −l, so l points at φ_in + π and v at
    # φ_in + φ_diff + π) the look-up returns that bin, and the Explorer's own index formula picks it.
    idx = np.stack(np.meshgrid(*[np.arange(k) for k in dims], indexing="ij"), -1).reshape(-1, 4)
    centre = (idx + 0.5) / np.array(dims) * np.array([HALF_PI, HALF_PI, TAU, TAU])
    l = _direction(centre[:, 0], centre[:, 3] + np.pi)
    v = _direction(centre[:, 1], centre[:, 3] + centre[:, 2] + np.pi)
    assert np.array_equal(_explorer_bins(l, v, dims), idx)
    got = t.eval(l.astype(np.float32), v.astype(np.float32), (0, 0, 1), (1, 0, 0))
    ref = want[tuple(idx.T)]
    holes = ~t.valid[tuple(idx.T)]
    np.testing.assert_allclose(got[~holes], ref[~holes], rtol=2e-5, atol=1e-6)
    # A cell without data holds 0 and is interpolated as 0: about 0 at its centre.
    assert holes.sum() == 1 and np.abs(got[holes]).max() < 1e-4
    # scale multiplies the stored values (10 matches the BRDF Explorer's display).
    t10 = AnisotropicTabulated.from_bytes(data, scale=10.0)
    np.testing.assert_allclose(t10.values, want * 10.0, rtol=1e-6)


def test_a_half_file_is_completed_by_reciprocity() -> None:
    dims = (4, 4, 6, 8)
    values = np.random.default_rng(2).uniform(0.1, 1.0, (*dims, 3)).astype(np.float32)
    t = AnisotropicTabulated.from_bytes(_dat(dims, values, half=1))
    assert t.half_data
    l, v = _pairs(np.random.default_rng(3), 500)
    a = t.eval(l, v, (0, 0, 1), (1, 0, 0))
    b = t.eval(v, l, (0, 0, 1), (1, 0, 0))
    # Exchanged, the other half of φ_diff reads the same cells (up to the rounding of the angles).
    np.testing.assert_allclose(a, b, rtol=1e-4, atol=1e-6)


def test_the_writer_round_trips_bit_for_bit(tmp_path: Path) -> None:
    t = AnisotropicTabulated.from_model(brdfpy.model("ward", **WARD), (4, 5, 8, 6))
    data = t.to_bytes()
    assert len(data) == 64 + 12 * 4 * 5 * 8 * 6
    assert struct.unpack("<16i", data[:64]) == (4, 5, 8, 6, 0, 0, 1, 0, 0, 0, 3, 0, 0, 0, 0, 0)
    back = AnisotropicTabulated.from_bytes(data)
    assert back.values.tobytes() == t.values.tobytes() and back.to_bytes() == data
    path = tmp_path / "ward.dat"
    t.write_mit(path)
    assert path.read_bytes() == data
    assert AnisotropicTabulated.read_mit(path).values.tobytes() == t.values.tobytes()
    # A file with holes marked -1 in every channel (what the writer writes) comes back byte for byte.
    values = np.random.default_rng(4).uniform(0, 1, (2, 3, 4, 5, 3)).astype(np.float32)
    values[0, 1, 2, :] = -1.0
    hand = _dat((2, 3, 4, 5), values, half=1)
    assert AnisotropicTabulated.from_bytes(hand).to_bytes() == hand
    # Through the constructor, with the mask.
    again = AnisotropicTabulated(back.values, back.valid, half_data=back.half_data)
    assert again.to_bytes() == data
    scaled = t.to_bytes(scale=10.0)
    np.testing.assert_allclose(
        AnisotropicTabulated.from_bytes(scaled, scale=10.0).values, t.values, rtol=1e-6
    )


def _with_header(data: bytes, k: int, x: int) -> bytes:
    return data[: 4 * k] + struct.pack("<i", x) + data[4 * k + 4 :]


def test_corrupt_files_are_refused_naming_the_argument_and_the_field(tmp_path: Path) -> None:
    good = _dat((2, 2, 3, 4), np.full((2, 2, 3, 4, 3), 0.5, np.float32))
    cases = [
        (good[:20], "truncated header"),
        (good[:-4], "truncated"),
        (good + b"\0\0\0\0", "trailing"),
        (_with_header(good, 0, 0), "header[0] (bins of theta_in)"),
        (_with_header(good, 2, -3), "header[2] (bins of phi_diff)"),
        (_with_header(good, 1, 2**31 - 1), "theta_out must have 1 to 4096 bins"),
        (_with_header(good, 6, 0), "paramType"),
        (_with_header(good, 7, 1), "binType"),
        (_with_header(good, 9, 5), "half_data"),
        (_with_header(good, 10, 1), "num_channels"),
        (struct.pack("<16i", 4000, 4000, 4000, 4000, 0, 0, 1, 0, 0, 0, 3, 0, 0, 0, 0, 0), "exceed"),
        (good[:64] + struct.pack("<f", np.nan) + good[68:], "value 0 of channel 0 is not finite"),
    ]
    for data, what in cases:
        with pytest.raises(brdfpy.BrdfError, match=r"^data: ") as e:
            AnisotropicTabulated.from_bytes(data)
        assert what in str(e.value), (what, str(e.value))
    p = tmp_path / "bad.dat"
    p.write_bytes(good[:-1])
    with pytest.raises(brdfpy.BrdfError, match=r"bad\.dat: data: .*truncated"):
        AnisotropicTabulated.read_mit(p)
    with pytest.raises(FileNotFoundError):
        AnisotropicTabulated.read_mit(tmp_path / "missing.dat")
    with pytest.raises(TypeError, match=r"^data: expected bytes"):
        AnisotropicTabulated.from_bytes(10**12)  # type: ignore[arg-type]
    for scale in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match=r"^scale: "):
            AnisotropicTabulated.from_bytes(good, scale=scale)
    with pytest.raises(TypeError, match=r"^scale: "):
        AnisotropicTabulated.from_bytes(good, scale="10")  # type: ignore[arg-type]
    m = brdfpy.model("lambert")
    with pytest.raises(brdfpy.BrdfError, match=r"^dims: theta_in"):
        AnisotropicTabulated.from_model(m, (0, 2, 2, 2))
    with pytest.raises(ValueError, match=r"^dims: expected 4"):
        AnisotropicTabulated.from_model(m, (2, 2, 2))  # type: ignore[arg-type]
    with pytest.raises(brdfpy.BrdfError, match=r"^dims: .*exceed"):
        AnisotropicTabulated.from_model(m, (4096, 4096, 4096, 4096))
    with pytest.raises(TypeError, match=r"^model: "):
        AnisotropicTabulated.from_model("ward", (2, 2, 2, 2))  # type: ignore[arg-type]
    with pytest.raises(brdfpy.BrdfError, match=r"^values: expected shape"):
        AnisotropicTabulated(np.ones((2, 2, 2, 3)))
    with pytest.raises(brdfpy.BrdfError, match=r"^values: .*finite and >= 0.*cell 0"):
        AnisotropicTabulated(np.full((1, 1, 1, 2, 3), -1.0))
    with pytest.raises(brdfpy.BrdfError, match=r"^valid: expected shape"):
        AnisotropicTabulated(np.ones((1, 1, 1, 2, 3)), np.ones((1, 1, 2), bool))
    with pytest.raises(TypeError, match=r"^valid: "):
        AnisotropicTabulated(np.ones((1, 1, 1, 2, 3)), np.ones((1, 1, 1, 2)))
    with pytest.raises(TypeError, match=r"^half_data: "):
        AnisotropicTabulated(np.ones((1, 1, 1, 2, 3)), half_data=1)  # type: ignore[arg-type]


def test_a_table_of_an_isotropic_model_agrees_with_the_model_and_the_isotropic_table() -> None:
    ct = brdfpy.model("cook_torrance", roughness=0.35, kd=(0.5, 0.3, 0.2))
    l, v = _pairs(np.random.default_rng(5), 20000)
    truth = ct.eval(l, v, (0, 0, 1))
    errors = {}
    tables = {}
    for dims in [(16, 16, 64, 4), (32, 32, 128, 4)]:
        tables[dims] = AnisotropicTabulated.from_model(ct, dims).eval(l, v)
        errors[dims] = _rel_rms(tables[dims], truth)
    iso_t = measured.Tabulated.from_model(ct, (32, 32, 64)).eval(l, v, (0, 0, 1))
    iso = _rel_rms(iso_t, truth)
    # Measured: 0.0074 and 0.0018 (ratio 4.1: second order); the MERL-layout table 32x32x64: 0.0061. The φ_in
    # axis of an isotropic model is constant, so 4 bins hold it.
    print("4-D table of Cook-Torrance, relative RMS error:", errors, "isotropic 32x32x64:", iso)
    e = list(errors.values())
    assert e[1] < 0.003 and e[0] / e[1] > 3.5, errors
    # The two tables agree within the sum of their errors.
    assert _rel_rms(tables[(32, 32, 128, 4)], iso_t) < e[1] + iso, (errors, iso)


def test_a_table_of_ward_converges_to_ward_at_second_order() -> None:
    ward = brdfpy.model("ward", **WARD)
    l, v = _pairs(np.random.default_rng(6), 20000)
    t_axis = np.array([1.0, 0.0, 0.0], np.float32)
    truth = ward.eval(l, v, (0, 0, 1), t_axis)
    errors = []
    for n in (6, 12, 24):
        t = AnisotropicTabulated.from_model(ward, (n, n, 4 * n, 4 * n))
        errors.append(_rel_rms(t.eval(l, v, (0, 0, 1), t_axis), truth))
    rates = [np.log2(a / b) for a, b in zip(errors, errors[1:])]
    # Measured: errors 0.083, 0.019, 0.0049 (rates 2.1, 1.9).
    print("4-D table of Ward (0.25, 0.5), relative RMS error at n = 6, 12, 24:", errors, "rates", rates)
    assert min(rates) > 1.7, (errors, rates)
    assert errors[-1] < 0.007, errors


def test_a_table_of_a_reciprocal_model_is_reciprocal_and_follows_its_tangent() -> None:
    ward = brdfpy.model("ward", **WARD)
    t = AnisotropicTabulated.from_model(ward, (16, 16, 64, 64))
    l, v = _pairs(np.random.default_rng(7), 5000)
    a, b = t.eval(l, v, (0, 0, 1), (1, 0, 0)), t.eval(v, l, (0, 0, 1), (1, 0, 0))
    diff = np.abs(a - b).max() / np.abs(a).max()
    # Measured: 0.52 % of the peak: the bins sample l and v asymmetrically (φ_in is l's), so exchanging them
    # interpolates between other cells; the model itself is exactly reciprocal.
    print("reciprocity of the 16x16x64x64 table of Ward, worst difference / peak:", diff)
    assert diff < 0.01
    half = AnisotropicTabulated.from_model(ward, (16, 16, 32, 64), half_data=True)
    np.testing.assert_allclose(
        half.eval(l, v, (0, 0, 1), (1, 0, 0)), half.eval(v, l, (0, 0, 1), (1, 0, 0)), rtol=1e-4, atol=1e-6
    )
    # Turning the frame about the normal turns the table with it: a world rotation of everything agrees.
    rot = np.array([[0.6, -0.8, 0], [0.8, 0.6, 0], [0, 0, 1]], np.float32)
    c = t.eval(l @ rot.T, v @ rot.T, (0, 0, 1), rot @ np.array([1, 0, 0], np.float32))
    np.testing.assert_allclose(c, a, rtol=1e-3, atol=1e-5)
    assert _rel_rms(t.eval(l, v, (0, 0, 1), (0, 1, 0)), a) > 0.05


def test_the_table_as_a_model_evaluates_renders_and_pickles() -> None:
    ward = brdfpy.model("ward", alpha_x=0.3, alpha_y=0.6, kd=0.3, ks=0.4)
    t = AnisotropicTabulated.from_model(ward, (8, 8, 32, 32))
    m = t.as_model()
    assert (m.name, m.physical, m.anisotropic, m.params) == ("measured_anisotropic", True, True, {})
    l, v = _pairs(np.random.default_rng(8), 3000)
    tan = np.array([0.0, 1.0, 0.0], np.float32)
    assert np.array_equal(m.eval(l, v, (0, 0, 1), tan), t.eval(l, v, (0, 0, 1), tan))
    np.testing.assert_allclose(
        m.shade(l, v, (0, 0, 1), tan), t.eval(l, v, (0, 0, 1), tan) * np.maximum(l[:, 2:3], 0), rtol=1e-6
    )
    for obj in (t, m):
        again = pickle.loads(pickle.dumps(obj))
        assert np.array_equal(again.eval(l, v, (0, 0, 1), tan), obj.eval(l, v, (0, 0, 1), tan))
    assert "measured_anisotropic" in repr(m) or "AnisotropicTabulated" in repr(m)
    with pytest.raises(ValueError, match="built from a table"):
        brdfpy.model("measured_anisotropic")
    with pytest.raises(ValueError, match="_table"):
        brdfpy.Model("measured", _table=t._inner)

    # Rendering: the image of the table converges to the image of Ward.
    cam = brdfpy.Camera.perspective((0, 0, 3), (0, 0, 0), (0, 1, 0), 45)

    def render(material: brdfpy.Model) -> brdfpy.Image:
        scene = brdfpy.Scene(ambient_light=0.0)
        scene.add(brdfpy.icosphere(4), material)
        scene.add_light(brdfpy.DirectionalLight((-1, -1, -1), 3.0))
        return scene.render(cam, 96, 72, outputs="all")

    want = render(ward)
    inside = want.triangle_id >= 0
    errors = []
    for dims in [(8, 8, 32, 32), (16, 16, 64, 64)]:
        got = render(AnisotropicTabulated.from_model(ward, dims).as_model())
        assert np.array_equal(got.triangle_id, want.triangle_id)
        assert np.isfinite(got.hdr).all()
        errors.append(np.abs(got.hdr - want.hdr)[inside].sum() / np.abs(want.hdr)[inside].sum())
    # Measured: 0.011 and 0.0028 (ratio 3.9).
    print("rendered sphere, table against Ward (relative L1):", errors)
    assert errors[1] < 0.005 and errors[0] / errors[1] > 3.0, errors


def test_an_rgl_material_is_a_model() -> None:
    ward = brdfpy.model("ward", alpha_x=0.2, alpha_y=0.4)
    rgl = measured.RglBsdf.from_model(ward, n_theta_i=6, n_phi_i=7, grid=(16, 16))
    m = rgl.as_model()
    assert (m.name, m.physical, m.anisotropic) == ("rgl_bsdf", True, True)
    l, v = _pairs(np.random.default_rng(9), 500)
    tan = np.array([1.0, 0.2, 0.0], np.float32)
    assert np.array_equal(m.eval(l, v, (0, 0, 1), tan), rgl.eval(l, v, (0, 0, 1), tan))
    again = pickle.loads(pickle.dumps(m))
    assert np.array_equal(again.eval(l, v, (0, 0, 1), tan), m.eval(l, v, (0, 0, 1), tan))
    r2 = pickle.loads(pickle.dumps(rgl))
    assert r2.to_bytes() == rgl.to_bytes()
    scene = brdfpy.Scene(ambient_light=0.0)
    scene.add(brdfpy.icosphere(2), m)
    scene.add_light(brdfpy.DirectionalLight((-1, -1, -1), 3.0))
    img = scene.render(brdfpy.Camera.perspective((0, 0, 3), (0, 0, 0), (0, 1, 0), 45), 24, 18, outputs="all")
    assert np.isfinite(img.hdr).all() and img.hdr.max() > 0
    # Its 4-D resampling evaluates like it.
    t = rgl.to_anisotropic((12, 12, 48, 48))
    assert _rel_rms(t.eval(l, v), rgl.eval(l, v, (0, 0, 1), (1, 0, 0))) < 0.1
    with pytest.raises(ValueError, match="built from a table"):
        brdfpy.model("rgl_bsdf")


def test_ward_is_fitted_to_an_anisotropic_table_with_no_start() -> None:
    truth = {"kd": (0.4, 0.25, 0.1), "ks": 0.3, "alpha_x": 0.12, "alpha_y": 0.35}
    t = AnisotropicTabulated.from_model(brdfpy.model("ward", **truth), (24, 24, 96, 96))
    rep = measured.fit("ward", t, samples=6000, strategy="half_diff")
    print(rep)
    assert rep.converged
    p = rep.params
    assert abs(p["alpha_x"] - 0.12) < 0.01 and abs(p["alpha_y"] - 0.35) < 0.02, p
    np.testing.assert_allclose(p["kd"], truth["kd"], atol=0.02)
    assert rep.model.name == "ward"
    # The same samples as arrays with their tangents give the same fit; a turned tangent swaps the slopes.
    l, v, f = brdfpy._brdfpy.aniso_table_samples(t._inner, 6000, 0, 80.0, "half_diff")
    same = measured.fit("ward", l, v, (0, 0, 1), f, tangent=(1, 0, 0))
    assert same.params == rep.params
    turned = measured.fit("ward", l, v, (0, 0, 1), f, tangent=(0, 1, 0))
    assert abs(turned.params["alpha_x"] - 0.35) < 0.03, turned.params
    with pytest.raises(TypeError, match=r"^tangent: "):
        measured.fit("ward", t, tangent=(1, 0, 0))
    with pytest.raises(ValueError, match="tangent"):
        measured.fit("ward", l, v, (0, 0, 1), f, tangent=np.ones((3, 3), np.float32))
