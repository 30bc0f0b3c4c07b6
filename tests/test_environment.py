"""brdfpy.Environment: equirectangular radiance maps and built-ins that light a scene and are its background,
in the fast mode (SH irradiance + prefiltered map) and the Monte Carlo mode (MIS, ray-cast visibility)."""

from __future__ import annotations

import math
import pickle

import brdfpy
import numpy as np
import pytest

CAM = brdfpy.Camera.perspective(eye=(0, 0, 3), target=(0, 0, 0), fovy=45)


def sphere_scene(material: brdfpy.Model | str, env: brdfpy.Environment, level: int = 5) -> brdfpy.Scene:
    scene = brdfpy.Scene(environment=env)
    scene.add(brdfpy.icosphere(level), material)
    return scene


def render(scene: brdfpy.Scene, size: int = 64, **kw: object) -> brdfpy.Image:
    return scene.render(CAM, size, size, outputs=("hdr", "normal", "triangle_id"), **kw)  # type: ignore[arg-type]


def gradient(h: int = 128, w: int = 256, a: float = 1.0, b: float = 0.8) -> np.ndarray:
    """L(ω) = a + b·ω_y on an equirectangular grid (row centres)."""
    t = (np.arange(h) + 0.5) / h
    y = np.cos(np.pi * t)
    return np.broadcast_to((a + b * y)[:, None, None], (h, w, 3)).astype(np.float32).copy()


# -- the map ----------------------------------------------------------------------------------------------


def test_the_map_convention_puts_the_middle_ahead_and_the_first_row_at_the_zenith() -> None:
    img = np.zeros((32, 64, 3), np.float32)
    img[:, 32] = (1, 0, 0)  # the middle column: −z
    img[:, 48] = (0, 1, 0)  # three quarters: +x
    img[0] = (0, 0, 1)  # the zenith row
    env = brdfpy.Environment(img)
    r = env.radiance([[0, 0, -1], [1, 0, 0], [0, 1, 0]])
    assert r[0, 0] > 0.4 and r[1, 1] > 0.4 and r[2, 2] > 0.9
    turned = env.rotated(90)  # the map's +x is now seen toward −z
    assert turned.radiance([0, 0, -1])[1] > 0.4
    assert env.scaled(3.0).radiance([0, 1, 0])[2] == pytest.approx(3 * env.radiance([0, 1, 0])[2])


def test_built_ins_need_no_file() -> None:
    u = brdfpy.Environment.uniform((0.5, 1.0, 2.0))
    assert np.allclose(u.radiance(np.eye(3)), [0.5, 1.0, 2.0])
    sky = brdfpy.Environment.sky()
    up, down, side = sky.radiance([[0, 1, 0], [0, -1, 0], [1, 0, 0]])
    assert up[2] > up[0] and down.sum() < side.sum()  # a blue zenith, a darker ground
    studio = brdfpy.Environment.studio()
    assert studio.radiance([0, 1, 0])[0] > studio.radiance([0, -1, 0])[0]


@pytest.mark.parametrize(
    ("image", "match"),
    [
        (np.ones((4, 8), np.float32), "image: must have shape"),
        (np.ones((4, 8, 4), np.float32), r"image: must have shape \(height, width, 3\)"),
        (np.ones((0, 8, 3), np.float32), "image"),
        (np.full((4, 8, 3), np.nan, np.float32), "image: radiance must be finite"),
        (-np.ones((4, 8, 3), np.float32), "image: radiance must be finite and ≥ 0"),
    ],
)
def test_bad_images_are_refused_naming_the_argument(image: np.ndarray, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        brdfpy.Environment(image)


def test_bad_settings_are_refused_naming_them() -> None:
    with pytest.raises(ValueError, match="intensity"):
        brdfpy.Environment.uniform(intensity=-1.0)
    with pytest.raises(ValueError, match="rotation"):
        brdfpy.Environment.sky(rotation=math.inf)
    with pytest.raises(ValueError, match="radiance"):
        brdfpy.Environment.uniform(-1.0)
    with pytest.raises(TypeError, match="environment"):
        brdfpy.Scene(environment="sky")  # type: ignore[arg-type]
    scene = sphere_scene("lambert", brdfpy.Environment.uniform())
    with pytest.raises(ValueError, match="env_samples"):
        scene.render(CAM, 8, 8, env_mode="monte_carlo", env_samples=0)
    with pytest.raises(ValueError, match="env_mode"):
        scene.render(CAM, 8, 8, env_mode="path_tracing")


def test_an_environment_pickles() -> None:
    env = brdfpy.Environment(gradient(8, 16), rotation=30, intensity=2)
    back = pickle.loads(pickle.dumps(env))
    assert back.rotation == pytest.approx(30) and back.intensity == 2
    assert np.array_equal(back.image, env.image)


# -- background -------------------------------------------------------------------------------------------


def test_the_environment_is_the_background() -> None:
    scene = sphere_scene("lambert", brdfpy.Environment.sky())
    scene.instances[0].transform = np.diag([0.2, 0.2, 0.2, 1.0])  # a small sphere, mostly sky around it
    img = render(scene, 64)
    bg = img.triangle_id < 0
    # The top rows look up (bluer, the sky), the bottom rows down: not one colour.
    top, bottom = img.hdr[0][bg[0]].mean(axis=0), img.hdr[-1][bg[-1]].mean(axis=0)
    assert top[2] > top[0] and not np.allclose(top, bottom)
    # The centre column of the top row looks along the camera's ray there.
    ray = np.array([0.0, math.tan(math.radians(22.5)) * (1 - 1 / 64), -1.0])
    assert np.allclose(img.hdr[0, 32], scene.environment.radiance(ray / np.linalg.norm(ray)), rtol=0.05)  # type: ignore[union-attr]
    # Supersampled and tone-mapped outputs agree.
    ss = scene.render(CAM, 64, 64, samples=4, outputs=("hdr", "rgb"))
    assert np.allclose(ss.hdr[0, 32], img.hdr[0, 32], rtol=0.05) and ss.rgb[0, 32].max() > 0


# -- fast mode --------------------------------------------------------------------------------------------


def test_fast_mode_white_furnace_is_exact() -> None:
    img = render(sphere_scene(brdfpy.model("lambert", kd=1.0), brdfpy.Environment.uniform(1.0)))
    lit = img.triangle_id >= 0
    assert np.allclose(img.hdr[lit], 1.0, atol=2e-3)


def test_fast_mode_diffuse_matches_the_analytic_irradiance_of_a_gradient() -> None:
    env = brdfpy.Environment(gradient())
    img = render(sphere_scene(brdfpy.model("lambert", kd=0.5), env), 96)
    lit = img.triangle_id >= 0
    n_y = img.normal[..., 1][lit]
    # E(n)/π = a + (2/3)·b·n_y; kd·E/π reflected.
    want = 0.5 * (1.0 + 2.0 / 3.0 * 0.8 * n_y)
    assert np.abs(img.hdr[..., 1][lit] - want).max() < 5e-3 * want.max()


def test_metals_reflect_the_sky_and_keep_their_colour() -> None:
    cu = brdfpy.model("cook_torrance", roughness=0.2, metal="cu")
    white = brdfpy.model("cook_torrance", kd=0.0, ks=1.0, fresnel="none", roughness=0.2)
    img = render(sphere_scene(cu, brdfpy.Environment.sky()), 96)
    ref = render(sphere_scene(white, brdfpy.Environment.sky()), 96)
    lit = img.triangle_id >= 0
    assert (img.hdr[lit] > 0.02).all()  # lit on every side, none of the old black unlit half
    # Against a white mirror of the same roughness in the same (blue) sky: the copper tint.
    tint = img.hdr[lit].mean(axis=0) / ref.hdr[lit].mean(axis=0)
    assert tint[0] > tint[1] > tint[2], tint
    top, bottom = img.hdr[20, 48], img.hdr[76, 48]
    assert top.sum() > bottom.sum()  # the upper half mirrors the bright sky, the lower the ground


def test_ao_darkens_the_fast_mode_and_ambient_light_adds_to_it() -> None:
    env = brdfpy.Environment.uniform(1.0)
    scene = brdfpy.Scene(environment=env)
    scene.add(brdfpy.icosphere(4), "lambert")
    scene.add(brdfpy.plane(8.0, 96), "lambert", brdfpy.transforms.translate(0, -1, 0))
    cam = brdfpy.Camera.perspective(eye=(0, 0.8, 3.6), target=(0, -0.2, 0), fovy=45)
    plain = scene.render(cam, 96, 72, outputs=("hdr",)).hdr
    ao = scene.render(cam, 96, 72, ao=True, outputs=("hdr",)).hdr
    assert (ao <= plain + 1e-6).all() and (ao < 0.7 * plain).any()
    scene.ambient_light = 0.5
    both = scene.render(cam, 96, 72, outputs=("hdr",)).hdr
    assert np.all(both >= plain)


# -- Monte Carlo mode -------------------------------------------------------------------------------------


def test_monte_carlo_white_furnace_of_a_lambert_sphere() -> None:
    img = render(
        sphere_scene(brdfpy.model("lambert", kd=1.0), brdfpy.Environment.uniform(1.0), 4),
        48,
        env_mode="monte_carlo",
        env_samples=64,
    )
    v = img.hdr[img.triangle_id >= 0]
    assert np.isfinite(v).all()
    # Each pixel is a mean of 64 MIS iterations; their mean over ~1300 pixels is 1 within a few 1e-3.
    assert abs(v.mean() - 1.0) < 5e-3, v.mean()
    assert np.percentile(np.abs(v - 1.0), 99) < 0.1


def test_monte_carlo_f1_conductor_loses_only_single_scattering_energy() -> None:
    losses = []
    for r in (0.1, 0.4, 0.8):
        m = brdfpy.model("cook_torrance", kd=0.0, ks=1.0, fresnel="none", roughness=r)
        img = render(
            sphere_scene(m, brdfpy.Environment.uniform(1.0), 4), 48, env_mode="monte_carlo", env_samples=128
        )
        centre = img.hdr[22:26, 22:26, 1].mean()  # n·v ≈ 1
        albedo = float(brdfpy.checks.directional_albedo(m, [1.0])[0, 1])
        assert abs(centre - albedo) < 0.02, (r, centre, albedo)
        losses.append(1.0 - centre)
    # Single scattering loses more as the surface roughens (Kulla & Conty 2017): a few % at α = 0.1.
    assert 0 <= losses[0] < 0.05 and losses[0] < losses[1] < losses[2] < 0.7, losses


def test_monte_carlo_is_deterministic_across_thread_counts() -> None:
    scene = sphere_scene(brdfpy.model("cook_torrance", roughness=0.3), brdfpy.Environment.sky(), 3)
    before = brdfpy.get_num_threads()
    try:
        brdfpy.set_num_threads(1)
        a = render(scene, 32, env_mode="monte_carlo", env_samples=8, env_seed=5).hdr
        brdfpy.set_num_threads(2)
        b = render(scene, 32, env_mode="monte_carlo", env_samples=8, env_seed=5).hdr
    finally:
        brdfpy.set_num_threads(before)
    assert np.array_equal(a, b)
    c = render(scene, 32, env_mode="monte_carlo", env_samples=8, env_seed=6).hdr
    assert not np.array_equal(a, c)


def test_fast_mode_is_close_to_monte_carlo_on_a_diffuse_sphere() -> None:
    scene = sphere_scene(brdfpy.model("lambert", kd=0.7), brdfpy.Environment.sky(), 4)
    fast = render(scene, 48)
    mc = render(scene, 48, env_mode="monte_carlo", env_samples=256)
    lit = fast.triangle_id >= 0
    rel = np.abs(fast.hdr[lit] - mc.hdr[lit]).mean() / mc.hdr[lit].mean()
    assert rel < 0.04, rel


# -- HDR output -------------------------------------------------------------------------------------------


def read_rgbe(path: str) -> np.ndarray:
    """A minimal Radiance reader for flat scanlines (the oracle of the writer)."""
    with open(path, "rb") as f:
        data = f.read()
    _, _, rest = data.partition(b"\n\n")
    dims, _, px = rest.partition(b"\n")
    _, h, _, w = dims.split()
    a = np.frombuffer(px, np.uint8).reshape(int(h), int(w), 4).astype(np.float64)
    scale = np.where(a[..., 3] > 0, np.ldexp(1.0, a[..., 3].astype(int) - 136), 0.0)
    return (a[..., :3] + 0.5) * scale[..., None] * (a[..., 3:4] > 0)


def test_image_save_writes_radiance_hdr(tmp_path: object) -> None:
    img = render(sphere_scene(brdfpy.model("lambert", kd=0.8), brdfpy.Environment.sky(intensity=3.0), 4), 40)
    path = f"{tmp_path}/out.hdr"
    img.save(path)
    back = read_rgbe(path)
    assert back.shape == img.hdr.shape
    assert np.allclose(back, img.hdr, rtol=1.0 / 64, atol=1e-6)
    with pytest.raises(Exception, match="hdr"):
        sphere_scene("lambert", brdfpy.Environment.uniform()).render(CAM, 8, 8).save(f"{tmp_path}/x.hdr")


def test_environments_load_from_hdr_and_exr_files_and_bad_files_are_refused(tmp_path: object) -> None:
    img = render(sphere_scene(brdfpy.model("lambert", kd=0.8), brdfpy.Environment.sky(intensity=3.0), 4), 40)
    img.save(f"{tmp_path}/map.hdr")
    img.save(f"{tmp_path}/map.exr")
    hdr = brdfpy.Environment.load(f"{tmp_path}/map.hdr", rotation=10, intensity=2)
    exr = brdfpy.Environment.load(f"{tmp_path}/map.exr")
    assert hdr.shape == exr.shape == (40, 40) and hdr.rotation == pytest.approx(10) and hdr.intensity == 2
    assert np.array_equal(exr.image, img.hdr)  # 32-bit floats: exact
    assert np.allclose(hdr.image, img.hdr, rtol=1.0 / 64, atol=1e-6)
    with open(f"{tmp_path}/map.exr", "rb") as f:
        data = f.read()
    with open(f"{tmp_path}/cut.exr", "wb") as f:
        f.write(data[: len(data) // 2])
    with pytest.raises(ValueError, match=r"cut\.exr"):
        brdfpy.Environment.load(f"{tmp_path}/cut.exr")
    with open(f"{tmp_path}/bad.hdr", "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 40 +X 40\n\x02\x02")
    with pytest.raises(ValueError, match=r"bad\.hdr"):
        brdfpy.Environment.load(f"{tmp_path}/bad.hdr")
    with pytest.raises(ValueError, match=r"missing\.hdr"):
        brdfpy.Environment.load(f"{tmp_path}/missing.hdr")
    with pytest.raises(ValueError, match="extension"):
        brdfpy.Environment.load(f"{tmp_path}/map.png")
