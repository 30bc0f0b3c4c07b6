"""Textures (``brdfpy.Texture``): filtering against NumPy references written here (nearest, bilinear with
every wrap mode, the box-filtered mip chain, trilinear with its level of detail), sRGB decoding, and
renders: a checkerboard quad seen at an angle against the ray-traced expectation at pixel centres,
mip-mapping removing the aliasing of a fine checker at grazing angles, parameters bound to textures,
normal, occlusion and emission maps, and bad input."""

from __future__ import annotations

import math

import brdfpy
import numpy as np
import pytest

RNG = np.random.default_rng(12)


# -- NumPy references ------------------------------------------------------------------------------------


def wrap_index(i: np.ndarray, n: int, wrap: str) -> np.ndarray:
    if wrap == "repeat":
        return np.mod(i, n)
    if wrap == "clamp":
        return np.clip(i, 0, n - 1)
    k = np.mod(i, 2 * n)  # mirrored repeat: 0 1 .. n-1 n-1 .. 1 0
    return np.where(k >= n, 2 * n - 1 - k, k)


def ref_bilinear(img: np.ndarray, uv: np.ndarray, wrap: str) -> np.ndarray:
    """Bilinear interpolation of texel centres at (u W − ½, v H − ½), glTF's v-down convention."""
    h, w = img.shape[:2]
    x = uv[:, 0].astype(np.float64) * w - 0.5
    y = uv[:, 1].astype(np.float64) * h - 0.5
    i, j = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    a, b = (x - i)[:, None], (y - j)[:, None]
    i0, i1 = wrap_index(i, w, wrap), wrap_index(i + 1, w, wrap)
    j0, j1 = wrap_index(j, h, wrap), wrap_index(j + 1, h, wrap)
    return (
        img[j0, i0] * (1 - a) * (1 - b)
        + img[j0, i1] * a * (1 - b)
        + img[j1, i0] * (1 - a) * b
        + img[j1, i1] * a * b
    )


def ref_nearest(img: np.ndarray, uv: np.ndarray, wrap: str) -> np.ndarray:
    h, w = img.shape[:2]
    i = np.floor(uv[:, 0].astype(np.float64) * w).astype(np.int64)
    j = np.floor(uv[:, 1].astype(np.float64) * h).astype(np.int64)
    return img[wrap_index(j, h, wrap), wrap_index(i, w, wrap)]


def ref_box_1d(a: np.ndarray, axis: int) -> np.ndarray:
    """Area average onto max(1, n // 2) cells, from the integral of the piecewise-constant signal."""
    a = np.moveaxis(a.astype(np.float64), axis, 0)
    n = a.shape[0]
    m = max(1, n // 2)
    cum = np.concatenate([np.zeros((1, *a.shape[1:])), np.cumsum(a, axis=0)])
    edges = np.arange(m + 1) * n / m

    def integral(x: float) -> np.ndarray:
        k = min(math.floor(x), n - 1)
        return cum[k] + (x - k) * a[k]

    out = np.stack([(integral(edges[i + 1]) - integral(edges[i])) / (n / m) for i in range(m)])
    return np.moveaxis(out, 0, axis)


def ref_levels(img: np.ndarray) -> list[np.ndarray]:
    levels = [img.astype(np.float64)]
    while levels[-1].shape[0] > 1 or levels[-1].shape[1] > 1:
        levels.append(ref_box_1d(ref_box_1d(levels[-1], 1), 0))
    return levels


def rgba(x: np.ndarray) -> np.ndarray:
    """RGBA as ``Texture.sample`` returns it: grey for one channel, alpha 1 for three."""
    if x.ndim == 1 or x.shape[-1] == 1:
        g = x.reshape(-1, 1)
        return np.concatenate([g, g, g, np.ones_like(g)], axis=1)
    if x.shape[-1] == 3:
        return np.concatenate([x, np.ones_like(x[:, :1])], axis=1)
    return x


# -- filtering -------------------------------------------------------------------------------------------


@pytest.mark.parametrize("wrap", ["repeat", "clamp", "mirror"])
def test_bilinear_and_nearest_match_the_numpy_reference_for_every_wrap_mode(wrap: str) -> None:
    img = RNG.random((5, 7, 3)).astype(np.float32)
    uv = RNG.uniform(-2.5, 3.5, (400, 2)).astype(np.float32)
    for filt, ref in (("bilinear", ref_bilinear), ("nearest", ref_nearest)):
        t = brdfpy.Texture(img, wrap=wrap, filter=filt)
        got = t.sample(uv)
        np.testing.assert_allclose(got, rgba(ref(img, uv, wrap)), atol=2e-6, err_msg=f"{filt} {wrap}")


def test_uv_origin_is_the_top_left_of_the_image_and_v_grows_downward() -> None:
    img = np.zeros((2, 2), np.float32)
    img[0, 1] = 1.0  # top row, right column
    t = brdfpy.Texture(img, filter="nearest")
    assert t.sample([[0.75, 0.25]])[0, 0] == 1.0
    assert t.sample([[0.25, 0.25]])[0, 0] == 0.0
    assert t.sample([[0.75, 0.75]])[0, 0] == 0.0


def test_the_mip_chain_is_the_area_average_of_the_level_above_it_also_for_odd_sizes() -> None:
    img = RNG.random((12, 7, 4)).astype(np.float32)
    got = brdfpy.Texture(img).levels()
    want = ref_levels(img)
    assert [g.shape[:2] for g in got] == [w.shape[:2] for w in want] == [(12, 7), (6, 3), (3, 1), (1, 1)]
    for g, w in zip(got, want):
        np.testing.assert_allclose(g, w, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(got[-1].reshape(4), img.reshape(-1, 4).mean(axis=0), rtol=1e-5)
    # Without mip-mapping there is one level.
    assert len(brdfpy.Texture(img, filter="bilinear").levels()) == 1


def test_trilinear_blends_the_two_levels_around_lambda_from_the_uv_derivatives() -> None:
    img = RNG.random((16, 16)).astype(np.float32)
    t = brdfpy.Texture(img, wrap="repeat")
    levels = ref_levels(img[..., None])
    uv = RNG.uniform(0, 1, (300, 2)).astype(np.float32)
    # Footprints of 0.5 to 20 texels per screen step along a random direction, y a shorter one.
    rho = np.exp(RNG.uniform(np.log(0.5), np.log(20.0), 300))
    ang = RNG.uniform(0, 2 * np.pi, 300)
    dx = (np.stack([np.cos(ang), np.sin(ang)], 1) * (rho / 16)[:, None]).astype(np.float32)
    dy = (np.stack([-np.sin(ang), np.cos(ang)], 1) * (0.5 * rho / 16)[:, None]).astype(np.float32)
    got = t.sample(uv, dx, dy)[:, 0]
    lam = np.clip(np.log2(np.maximum(np.hypot(*(dx * 16).T), np.hypot(*(dy * 16).T))), 0, len(levels) - 1)
    d = np.floor(lam).astype(int)
    want = np.empty(300)
    for k in range(300):
        a = ref_bilinear(levels[d[k]], uv[k : k + 1], "repeat")[0, 0]
        b = ref_bilinear(levels[min(d[k] + 1, len(levels) - 1)], uv[k : k + 1], "repeat")[0, 0]
        f = lam[k] - d[k]
        want[k] = a * (1 - f) + b * f
    np.testing.assert_allclose(got, want, atol=1e-5)
    # The coarsest level (far beyond the image) is the mean.
    far = t.sample([[0.3, 0.3]], [[100.0, 0.0]], [[0.0, 100.0]])[0, 0]
    assert abs(far - img.mean()) < 1e-5


def test_8_bit_data_is_srgb_decoded_by_default_and_16_bit_and_float_stay_linear() -> None:
    v = np.arange(256, dtype=np.uint8).reshape(16, 16)
    s = v / 255.0
    srgb = np.where(s <= 0.04045, s / 12.92, ((s + 0.055) / 1.055) ** 2.4)
    np.testing.assert_allclose(brdfpy.Texture(v).levels()[0][..., 0], srgb, atol=2e-6)
    np.testing.assert_allclose(brdfpy.Texture(v, colorspace="linear").levels()[0][..., 0], s, atol=1e-7)
    w = (np.arange(256, dtype=np.uint16) * 257).reshape(16, 16)
    np.testing.assert_allclose(brdfpy.Texture(w).levels()[0][..., 0], w / 65535.0, atol=1e-7)
    f = RNG.random((4, 4, 3))
    np.testing.assert_allclose(brdfpy.Texture(f).levels()[0], f, atol=1e-7)
    # RGBA: the alpha channel of 8-bit data is linear.
    a = np.full((1, 1, 4), 128, np.uint8)
    got = brdfpy.Texture(a).levels()[0][0, 0]
    assert abs(got[3] - 128 / 255) < 1e-7 and abs(got[0] - 0.2158605) < 1e-5


def test_image_files_are_read_through_pillow(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from PIL import Image as PILImage

    a = RNG.integers(0, 256, (6, 5, 3), dtype=np.uint8)
    PILImage.fromarray(a).save(tmp_path / "t.png")
    t = brdfpy.Texture(tmp_path / "t.png", filter="nearest")
    assert (t.width, t.height, t.channels) == (5, 6, 3)
    np.testing.assert_allclose(t.levels()[0], brdfpy.Texture(a).levels()[0])


# -- renders ---------------------------------------------------------------------------------------------


def quad(size: float = 2.0, repeat: float = 1.0) -> brdfpy.Mesh:
    """The square y = 0, |x|, |z| ≤ size/2, facing +y; u along +x, v along +z (down the image = toward
    the viewer of a camera looking along −z)."""
    h = size / 2
    v = [[-h, 0, -h], [h, 0, -h], [h, 0, h], [-h, 0, h]]
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32) * repeat
    return brdfpy.Mesh(v, [[0, 2, 1], [0, 3, 2]], [[0, 1, 0]] * 4, uvs=uv)


def checker(n: int, cells: int) -> np.ndarray:
    i = np.arange(n) * cells // n
    return ((i[:, None] + i[None, :]) % 2).astype(np.float32) * 0.8 + 0.1  # 0.1 and 0.9


def lit_scene(mesh: brdfpy.Mesh, model: brdfpy.Model, **add: object) -> brdfpy.Scene:
    scene = brdfpy.Scene()
    scene.add(mesh, model, **add)  # type: ignore[arg-type]
    scene.add_light(brdfpy.DirectionalLight(direction=(0, -1, 0)))  # straight down: n·l = 1 on the quad
    return scene


def test_a_checkerboard_quad_seen_at_an_angle_shows_the_colour_of_the_texel_each_pixel_centre_sees() -> None:
    tex = brdfpy.Texture(checker(8, 8), filter="nearest")
    scene = lit_scene(quad(), brdfpy.model("lambert", kd=tex))
    eye, target, fovy, w, h = np.array([0.3, 1.6, 2.2]), np.array([0.0, 0.0, -0.2]), 40.0, 96, 72
    cam = brdfpy.Camera.perspective(eye=tuple(eye), target=tuple(target), fovy=fovy)
    img = scene.render(cam, w, h, outputs=["hdr"]).hdr[..., 0]
    # Ray through each pixel centre (right-handed look-at, y up), onto the plane y = 0.
    f = (target - eye) / np.linalg.norm(target - eye)
    r = np.cross(f, [0, 1, 0])
    r /= np.linalg.norm(r)
    up = np.cross(r, f)
    t = math.tan(math.radians(fovy) / 2)
    xs = (2 * (np.arange(w) + 0.5) / w - 1) * t * w / h
    ys = (1 - 2 * (np.arange(h) + 0.5) / h) * t
    d = f + xs[None, :, None] * r + ys[:, None, None] * up
    s = -eye[1] / d[..., 1]
    p = eye + s[..., None] * d
    u, v = (p[..., 0] + 1) / 2, (p[..., 2] + 1) / 2
    inside = (u > 0) & (u < 1) & (v > 0) & (v < 1)
    # Away from the cells' edges (a pixel's ray and the renderer's may differ by float rounding).
    fu, fv = (u * 8) % 1, (v * 8) % 1
    clear = inside & (np.minimum(fu, 1 - fu) > 0.02) & (np.minimum(fv, 1 - fv) > 0.02)
    kd = np.where((np.floor(u * 8) + np.floor(v * 8)) % 2 == 1, 0.9, 0.1)
    want = kd / np.pi
    assert clear.sum() > 2000
    np.testing.assert_allclose(img[clear], want[clear], rtol=1e-4)
    assert np.all(img[~inside & (np.minimum.reduce([u, 1 - u, v, 1 - v]) < -0.02)] == 0)


def test_mip_mapping_removes_the_aliasing_of_a_fine_checker_at_grazing_angles() -> None:
    """A 256² checker of 1-texel cells repeated 16 times on a floor seen at grazing angle: far away each
    pixel covers many cells, and its colour should be the mean. Nearest sampling aliases (pixels of 0.1
    and 0.9), trilinear gives the mean."""
    img = np.indices((256, 256)).sum(axis=0) % 2 * 0.8 + 0.1
    floor = quad(40.0, repeat=16.0)
    cam = brdfpy.Camera.perspective(eye=(0, 0.6, 19.5), target=(0, 0, 0), fovy=40)
    far = slice(60, 72)  # the floor 6 to 20 units away (the horizon is near row 55): many texels a pixel
    out = {}
    for filt in ("nearest", "trilinear"):
        scene = lit_scene(
            floor, brdfpy.model("lambert", kd=brdfpy.Texture(img.astype(np.float32), filter=filt))
        )
        hdr = scene.render(cam, 160, 120, outputs=["hdr"]).hdr[far, :, 0] * np.pi
        out[filt] = hdr
    mean = 0.5
    tri, near = out["trilinear"], out["nearest"]
    assert tri.std() < 0.03, tri.std()
    assert abs(tri.mean() - mean) < 0.02, tri.mean()
    assert near.std() > 0.25, near.std()  # aliasing: about ±0.4 around the mean
    assert np.mean((tri - mean) ** 2) < 0.01 * np.mean((near - mean) ** 2)


def uv_sphere(rings: int = 24, segments: int = 48) -> brdfpy.Mesh:
    th = np.linspace(0, np.pi, rings + 1)
    ph = np.linspace(0, 2 * np.pi, segments + 1)
    t, p = np.meshgrid(th, ph, indexing="ij")
    pos = np.stack([np.sin(t) * np.cos(p), np.cos(t), -np.sin(t) * np.sin(p)], -1).reshape(-1, 3)
    uv = np.stack([p / (2 * np.pi), t / np.pi], -1).reshape(-1, 2)
    k = np.arange(rings * (segments + 1)).reshape(rings, segments + 1)[:, :-1].ravel()
    a, b, c, d = k, k + 1, k + segments + 1, k + segments + 2
    faces = np.concatenate([np.stack([a, c, b], 1), np.stack([b, c, d], 1)])
    return brdfpy.Mesh(pos, faces, pos, uvs=uv)


def sphere_render(model: brdfpy.Model, **add: object) -> np.ndarray:
    scene = brdfpy.Scene(ambient_light=0.2)
    scene.add(uv_sphere(), model, **add)  # type: ignore[arg-type]
    scene.add_light(brdfpy.DirectionalLight(direction=(-1, -1, -1), color=2.0))
    cam = brdfpy.Camera.perspective(eye=(0, 0.5, 3), fovy=45)
    return scene.render(cam, 96, 96, outputs=["hdr"]).hdr


def test_a_parameter_bound_to_a_constant_texture_renders_as_the_untextured_model_with_that_constant() -> None:
    kd = np.full((8, 8, 3), [0.6, 0.3, 0.1], np.float32)
    rough = np.zeros((8, 8, 3), np.float32)
    rough[..., 1] = 0.35  # glTF packs roughness in G
    m = brdfpy.model(
        "cook_torrance",
        kd=brdfpy.Texture(kd),
        roughness=brdfpy.Texture(rough).channel(1),
        f0=0.04,
    )
    assert isinstance(m, brdfpy.TexturedModel)
    plain = brdfpy.model("cook_torrance", kd=(0.6, 0.3, 0.1), roughness=0.35, f0=0.04)
    a, b = sphere_render(m), sphere_render(plain)
    assert (b > 0).any()
    np.testing.assert_allclose(a, b, rtol=2e-5, atol=1e-7)


def test_every_colour_or_scalar_parameter_of_every_model_can_be_textured() -> None:
    checked = 0
    for name in brdfpy.models():
        for p in brdfpy.model_info(name)["params"]:
            if p["kind"] not in ("color", "scalar"):
                continue
            default = p["default"][0] if p["kind"] == "color" else p["default"]
            value = float(np.float32(min(max(float(default), p["min"]), p["max"])))
            tex = brdfpy.Texture(np.full((4, 4), value, np.float32), filter="nearest")
            got = sphere_render(brdfpy.model(name, **{p["name"]: tex}))
            const = value if p["kind"] == "scalar" else [value] * 3
            want = sphere_render(brdfpy.model(name, **{p["name"]: const}))
            np.testing.assert_allclose(got, want, rtol=1e-5, atol=1e-7, err_msg=f"{name}.{p['name']}")
            checked += 1
    assert checked > 40


def test_a_textured_render_is_bit_identical_for_any_number_of_threads() -> None:
    m = brdfpy.model(
        "cook_torrance",
        kd=brdfpy.Texture(RNG.random((64, 64, 3))),
        roughness=brdfpy.Texture(RNG.random((32, 32)) * 0.5 + 0.1),
    )
    before = brdfpy.get_num_threads()
    try:
        brdfpy.set_num_threads(1)
        a = sphere_render(m)
        brdfpy.set_num_threads(2)
        b = sphere_render(m)
    finally:
        brdfpy.set_num_threads(before)
    assert np.array_equal(a, b)


def test_a_flat_normal_map_changes_nothing_and_a_tilted_one_turns_the_shading() -> None:
    m = brdfpy.model("lambert", kd=brdfpy.Texture(np.full((4, 4, 3), 0.5, np.float32)))
    flat = np.full((4, 4, 3), [0.5, 0.5, 1.0], np.float32)
    base = sphere_render(m)
    np.testing.assert_allclose(sphere_render(m, normal_map=brdfpy.Texture(flat)), base, rtol=1e-5, atol=1e-6)
    tilted = np.full((4, 4, 3), [0.8, 0.5, 0.9], np.float32)
    assert np.abs(sphere_render(m, normal_map=brdfpy.Texture(tilted)) - base).max() > 0.02


def test_occlusion_map_darkens_only_the_ambient_term_and_emission_map_multiplies_the_emission() -> None:
    m = brdfpy.model("lambert", kd=0.5)
    half = brdfpy.Texture(np.full((4, 4), 0.5, np.float32))
    scene = brdfpy.Scene(ambient_light=0.4)
    scene.add(
        quad(),
        m,
        ambient=0.5,
        occlusion_map=half,
        emission=brdfpy.Texture(np.full((2, 2, 3), [0.2, 0.0, 0.1], np.float32)),
    )
    cam = brdfpy.Camera.perspective(eye=(0, 2.5, 1.0), target=(0, 0, 0), fovy=30)
    img = scene.render(cam, 32, 32, outputs=["hdr"]).hdr
    # No light: ambient 0.5 · 0.4 · occlusion (1 + 1·(0.5 − 1)) + emission.
    np.testing.assert_allclose(img[16, 16], [0.1 + 0.2, 0.1, 0.1 + 0.1], rtol=1e-5)


# -- bad input -------------------------------------------------------------------------------------------


def test_bad_textures_and_texture_coordinates_are_refused_with_clear_errors() -> None:
    a = np.full((4, 4, 3), 0.5, np.float32)
    a[2, 1, 0] = np.nan
    with pytest.raises(ValueError, match=r"texel \(1, 2\) channel 0 is NaN"):
        brdfpy.Texture(a)
    with pytest.raises(ValueError, match=r"negative|≥ 0"):
        brdfpy.Texture(-np.ones((2, 2), np.float32))
    with pytest.raises(ValueError, match="zero size"):
        brdfpy.Texture(np.zeros((0, 4, 3), np.float32))
    with pytest.raises(ValueError, match="1, 3 or 4 channels"):
        brdfpy.Texture(np.zeros((2, 2, 2), np.float32))
    with pytest.raises(TypeError, match="uint8 or uint16"):
        brdfpy.Texture(np.zeros((2, 2), np.int64))
    with pytest.raises(ValueError, match="wrap"):
        brdfpy.Texture(np.zeros((2, 2), np.float32), wrap="tile")
    with pytest.raises(ValueError, match="uvs: 3 rows for 4 vertices"):
        brdfpy.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2]], uvs=[[0, 0]] * 3)
    with pytest.raises(ValueError, match="uvs: row 1 is not finite"):
        brdfpy.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], uvs=[[0, 0], [np.nan, 0], [0, 1]])
    tex = brdfpy.Texture(np.full((2, 2, 3), 0.5, np.float32))
    m = brdfpy.model("lambert", kd=tex)
    scene = brdfpy.Scene()
    scene.add(brdfpy.icosphere(1), m)
    with pytest.raises(ValueError, match=r"kd.*no texture coordinates"):
        scene.render(brdfpy.Camera.perspective(eye=(0, 0, 3)), 16, 16)
    with pytest.raises(ValueError, match="texture coordinates"):
        m.eval([0, 0, 1], [0, 0, 1], [0, 0, 1])
    with pytest.raises(ValueError, match=r"scalar parameter.*channel"):
        brdfpy.model("cook_torrance", roughness=tex)
    with pytest.raises(ValueError, match=r"channel: must be in 0..2"):
        tex.channel(3)
    with pytest.raises(ValueError, match="normal_map: the mesh has no texture coordinates"):
        brdfpy.Scene().add(brdfpy.icosphere(1), "lambert", normal_map=tex)
