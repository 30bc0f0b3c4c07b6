"""brdfpy's renderer (``Scene.render``) against the independent reference rasterizer in
``tests/raster_oracle`` on small images: coverage (which triangle each pixel shows), HDR colour, depth and
normal buffers, for every shading algorithm, several lights and models, transforms, clipping and
off-screen geometry. Tolerances are stated and justified in ``raster_oracle/bridge.py``."""

from __future__ import annotations

from typing import Any

import brdfpy
import numpy as np
import pytest

from oracle import tonemap as otm
from raster_oracle import bridge as rb
from raster_oracle import geometry as og
from raster_oracle import raster as oraster

SHADINGS = ["flat", "gouraud", "phong", "quadratic"]


def mesh_obj(mesh: Any, **kw: Any) -> rb.Obj:
    """An ``Obj`` from a brdfpy mesh's own arrays (so both renderers draw the same float32 geometry)."""
    return rb.Obj(np.asarray(mesh.vertices), np.asarray(mesh.faces), np.asarray(mesh.normals), **kw)


def canonical(level: int = 3) -> rb.Spec:
    kd = np.array([0.8, 0.3, 0.2])
    sphere = mesh_obj(
        brdfpy.icosphere(level),
        model="blinn_phong_classic",
        params={"kd": tuple(kd), "ks": 0.5, "shininess": 32},
        ambient=tuple(0.05 * kd),
    )
    lights = [
        rb.Light("directional", {"direction": (-1, -1, -1), "color": 1.0}),
        rb.Light("point", {"position": (2, 2, 2), "intensity": 10.0, "attenuation": "inverse_square"}),
    ]
    return rb.Spec([sphere], lights, rb.Cam("perspective", {"eye": (0, 0, 3), "target": (0, 0, 0)}))


def torus_scene() -> rb.Spec:
    xf = og.translation((0.1, -0.1, 0.0)) @ og.rotation((1, 0.3, 0), 1.1) @ og.scaling((1.2, 1.0, 0.9))
    torus = mesh_obj(
        brdfpy.torus(20, 10),
        model="cook_torrance",
        params={"kd": (0.3, 0.2, 0.1), "ks": 0.8, "roughness": 0.25, "fresnel": "schlick", "f0": 0.5},
        ambient=0.02,
        transform=xf,
    )
    lights = [
        rb.Light("directional", {"direction": (0.3, -1, -0.5), "color": (0.9, 0.8, 0.6)}),
        rb.Light(
            "point",
            {"position": (-1.5, 1.0, 1.5), "intensity": (2.0, 3.0, 4.0), "attenuation": (1, 0.5, 0.25)},
        ),
        rb.Light(
            "spot",
            {
                "position": (1.0, 1.5, 2.0),
                "direction": (-0.5, -0.7, -1.0),
                "intensity": 8.0,
                "inner_angle": 10.0,
                "outer_angle": 25.0,
                "attenuation": "inverse_square",
            },
        ),
    ]
    cam = rb.Cam(
        "perspective", {"eye": (0.5, 1.2, 2.6), "target": (0, 0, 0), "fovy": 50, "near": 0.5, "far": 10}
    )
    return rb.Spec([torus], lights, cam, ambient_light=(0.5, 0.6, 0.7))


def two_objects() -> rb.Spec:
    ball = mesh_obj(
        brdfpy.icosphere(2),
        model="phong_classic",
        params={"kd": (0.2, 0.5, 0.8), "ks": 0.4, "shininess": 20},
        ambient=0.1,
        transform=og.translation((0.0, 0.5, 0.0)) @ og.scaling(0.5),
    )
    floor = mesh_obj(
        brdfpy.plane(3.0, 4), model="lambert", params={"kd": (0.7, 0.7, 0.6)}, emission=(0.05, 0.0, 0.0)
    )
    lights = [
        rb.Light("directional", {"direction": (-0.4, -1, -0.3), "color": 1.5}),
        rb.Light("point", {"position": (1, 2, 1), "intensity": 4.0, "attenuation": "none"}),
    ]
    cam = rb.Cam("orthographic", {"eye": (2, 2.5, 3), "target": (0, 0.3, 0), "height": 3.0})
    return rb.Spec([ball, floor], lights, cam, ambient_light=0.3, background=(0.1, 0.2, 0.3))


def check_render(
    spec: rb.Spec, width: int, height: int, shading: str, **kw: Any
) -> tuple[Any, oraster.Frame]:
    img, ref = rb.render_both(spec, width, height, shading, **kw)
    rb.assert_matches(img.hdr, ref.hdr, img.triangle_id, ref, spec, f"{shading} hdr")
    return img, ref


@pytest.mark.parametrize("shading", SHADINGS)
def test_canonical_scene_matches_reference(shading: str) -> None:
    spec = canonical()
    img, ref = check_render(spec, 96, 64, shading)
    assert img.hdr.shape == (64, 96, 3) and img.hdr.dtype == np.float32
    assert ref.covered.sum() > 1000
    rb.assert_matches(img.depth, ref.depth, img.triangle_id, ref, spec, "depth", rtol=1e-5, buffer="depth")
    if shading != "gouraud":
        rb.assert_matches(img.normal, ref.normal, img.triangle_id, ref, spec, "normal", buffer="normal")


@pytest.mark.parametrize("shading", ["gouraud", "phong"])
def test_transformed_torus_three_lights_matches_reference(shading: str) -> None:
    check_render(torus_scene(), 80, 60, shading)


@pytest.mark.parametrize("shading", ["flat", "quadratic"])
def test_two_instances_orthographic_matches_reference(shading: str) -> None:
    spec = two_objects()
    img, ref = check_render(spec, 64, 48, shading)
    # orthographic window depth is linear in the view distance
    rb.assert_matches(img.depth, ref.depth, img.triangle_id, ref, spec, "depth", rtol=1e-5, buffer="depth")
    # face ids count over the instances in scene order: the floor's ids follow the ball's
    n_ball = len(np.asarray(spec.objects[0].faces))
    assert (np.asarray(img.triangle_id) >= n_ball).any() and (
        np.asarray(img.triangle_id)[img.triangle_id >= 0] < n_ball
    ).any()
    bg = ~ref.covered & ~ref.ambiguous()
    np.testing.assert_allclose(
        np.asarray(img.hdr)[bg], np.broadcast_to([0.1, 0.2, 0.3], (int(bg.sum()), 3)), rtol=1e-6
    )


def bumpy_ball() -> rb.Spec:
    # an icosphere with radially jittered vertices and computed (angle-weighted) normals: unlike a sphere
    # (where (n0 + n1).(p1 - p0) = 0 on every edge), here the quadratic term of van Overveld & Wyvill's
    # interpolation is far from zero, so "quadratic" and "phong" shading differ visibly
    rng = np.random.default_rng(7)
    v, f = og.icosphere(2)
    v = v * rng.uniform(0.8, 1.2, (len(v), 1))
    mesh = brdfpy.Mesh(v, f)
    obj = mesh_obj(mesh, model="blinn_phong_classic", params={"kd": 0.6, "ks": 0.4, "shininess": 24})
    lights = [rb.Light("directional", {"direction": (-0.3, -0.5, -1), "color": 1.0})]
    return rb.Spec([obj], lights, rb.Cam("perspective", {"eye": (0.2, 0.3, 3.2), "target": (0, 0, 0)}))


def test_quadratic_normals_on_a_bumpy_mesh_match_reference() -> None:
    spec = bumpy_ball()
    img, ref = check_render(spec, 64, 48, "quadratic")
    rb.assert_matches(img.normal, ref.normal, img.triangle_id, ref, spec, "normal", buffer="normal")
    phong = rb.reference(spec, 64, 48, "phong")
    c = rb.compare(img.normal, phong.normal, img.triangle_id, ref, spec, buffer="normal")
    assert c.max_excess > 0.05, "quadratic and phong normals should differ on this mesh"


@pytest.mark.parametrize("shading", SHADINGS)
def test_vertex_colours_tint_everything_but_emission(shading: str) -> None:
    mesh = brdfpy.icosphere(2)
    rng = np.random.default_rng(5)
    colors = rng.uniform(0.1, 1.0, (mesh.n_vertices, 3))
    obj = mesh_obj(
        mesh,
        model="phong_classic",
        params={"kd": 0.7, "ks": 0.3, "shininess": 10},
        ambient=0.1,
        emission=(0.02, 0.0, 0.05),
        colors=colors,
    )
    lights = [rb.Light("point", {"position": (1, 2, 3), "intensity": 12.0})]
    spec = rb.Spec([obj], lights, rb.Cam("perspective", {"eye": (0, 0.5, 3)}))
    check_render(spec, 48, 36, shading)


ISOTROPIC_MODELS: list[tuple[str, dict[str, Any]]] = [
    ("lambert", {}),
    ("lambert_classic", {}),
    ("oren_nayar", {"sigma": 0.5}),
    ("oren_nayar_full", {}),
    ("phong_classic", {}),
    ("blinn_phong_classic", {}),
    ("phong", {"shininess": 16}),
    ("blinn_phong", {}),
    (
        "cook_torrance",
        {"distribution": "beckmann", "fresnel": "conductor", "eta": (0.2, 0.4, 1.4), "k": (3.6, 2.4, 1.8)},
    ),
    ("strauss", {}),
    ("ward", {"alpha_x": 0.2, "alpha_y": 0.2}),
    ("ashikhmin_shirley", {"nu": 40, "nv": 40}),
    ("lafortune", {}),
]
# ``toon`` is left out: its bands jump at thresholds of n.l, so float32 vs float64 may put a pixel in
# the other band, a difference no tolerance on the value can describe.


@pytest.mark.parametrize(("name", "params"), ISOTROPIC_MODELS, ids=[m for m, _ in ISOTROPIC_MODELS])
def test_every_isotropic_model_renders_like_the_reference(name: str, params: dict[str, Any]) -> None:
    obj = mesh_obj(brdfpy.icosphere(2), model=name, params=params)
    lights = [
        rb.Light("directional", {"direction": (-0.5, -0.6, -1), "color": 2.0}),
        rb.Light("point", {"position": (-2, 1, 2), "intensity": 6.0}),
    ]
    spec = rb.Spec([obj], lights, rb.Cam("perspective", {"eye": (0.3, 0.4, 3), "target": (0, 0, 0)}))
    check_render(spec, 48, 36, "phong")


def floor_spec(normals: np.ndarray | None = None) -> rb.Spec:
    v = np.array([[-2, 0, 1], [2, 0, 1], [2, 0, -12], [-2, 0, -12]], float)
    f = np.array([[0, 1, 2], [0, 2, 3]])
    if normals is None:
        normals = np.array([[0, 1, 0], [1, 1, 0], [0, 1, 1], [-1, 1, 0]], float)
    obj = rb.Obj(v, f, normals, model="lambert")
    light = rb.Light("point", {"position": (0, 1, -2), "intensity": 3.0})
    return rb.Spec(
        [obj], [light], rb.Cam("perspective", {"eye": (0, 1, 3), "target": (0, 0, -3), "fovy": 60})
    )


def test_interpolation_is_perspective_correct() -> None:
    spec = floor_spec()
    img, ref = check_render(spec, 48, 36, "phong")
    rb.assert_matches(img.normal, ref.normal, img.triangle_id, ref, spec, "normal", buffer="normal")
    # the same comparison against screen-linear interpolation fails by far: the test can tell them apart
    affine = rb.reference(spec, 48, 36, "phong", perspective_correct=False)
    c = rb.compare(img.normal, affine.normal, img.triangle_id, affine, spec, buffer="normal")
    assert c.max_excess > 0.05


def test_gouraud_colours_are_interpolated_perspective_correctly() -> None:
    spec = floor_spec()
    check_render(spec, 48, 36, "gouraud")


def test_back_faces_are_culled_only_when_asked() -> None:
    # an inside-out sphere: with culling, its near half (now facing away) disappears and the inside of
    # its far half shows; without, the near half hides the far half again
    inside_out = mesh_obj(brdfpy.icosphere(2).flip_winding(), model="lambert", ambient=0.1)
    light = rb.Light("directional", {"direction": (0, 0, 1)})
    spec = rb.Spec([inside_out], [light], rb.Cam("perspective", {"eye": (0, 0, 3)}))
    culled, _ref_culled = check_render(spec, 32, 24, "phong")
    both, _ref_both = check_render(spec, 32, 24, "phong", cull_back_faces=False)
    centre_c, centre_b = culled.triangle_id[12, 16], both.triangle_id[12, 16]
    assert centre_c >= 0 and centre_b >= 0 and centre_c != centre_b
    assert (np.asarray(culled.depth)[12, 16]) > (np.asarray(both.depth)[12, 16])
    # one triangle seen from behind
    back = one_triangle([[0, 1, 0], [1, -1, 0], [-1, -1, 0]])
    img = rb.brdfpy_scene(back).render(rb.brdfpy_camera(back.camera), 32, 24, outputs="all")
    assert (np.asarray(img.triangle_id) == -1).all()
    check_render(back, 32, 24, "flat", cull_back_faces=False)


# ------------------------------------------------------------------------------ clipping, off screen


def ground_through_the_camera() -> rb.Spec:
    # a floor reaching from behind the eye to far ahead: every triangle touching the eye's row crosses
    # the near plane (the camera at height 0.3 looks slightly down)
    v, f = og.grid(4, 4)
    v = np.column_stack([v[:, 0] * 6, np.zeros(len(v)), v[:, 1] * 10 - 5])  # x in [-6, 6], z in [-15, 5]
    n = np.tile([0.0, 1.0, 0.0], (len(v), 1))
    # the grid is CCW seen from +z; seen from above it must be CCW about +y
    f = f[:, ::-1]
    obj = rb.Obj(v, f, n, model="lambert", params={"kd": 0.6}, ambient=0.05)
    lights = [rb.Light("point", {"position": (0, 1, -1), "intensity": 2.0})]
    cam = rb.Cam("perspective", {"eye": (0, 0.3, 0), "target": (0, 0, -2), "fovy": 70, "near": 0.2})
    return rb.Spec([obj], lights, cam)


@pytest.mark.parametrize("shading", ["gouraud", "phong"])
def test_triangles_crossing_the_near_plane_are_clipped_not_dropped(shading: str) -> None:
    spec = ground_through_the_camera()
    vp = rb.oracle_camera(spec.camera).view_projection(48 / 36)
    clip = np.column_stack([spec.objects[0].vertices, np.ones(len(spec.objects[0].vertices))]) @ vp.T
    crossing = [
        i
        for i, t in enumerate(np.asarray(spec.objects[0].faces))
        if len({bool(x) for x in clip[t, 2] + clip[t, 3] >= 0}) == 2
    ]
    assert crossing, "the scene must have triangles crossing the near plane"
    img, _ref = check_render(spec, 48, 36, shading)
    shown = set(np.unique(np.asarray(img.triangle_id)).tolist())
    assert shown & set(crossing), "no pixel shows a clipped triangle"
    # the lower part of the image is floor right in front of the camera, drawn by clipped triangles
    assert (np.asarray(img.triangle_id)[-3:] >= 0).all()


def one_triangle(v: Any, cam: rb.Cam | None = None) -> rb.Spec:
    obj = rb.Obj(
        np.asarray(v, float), [[0, 1, 2]], np.tile([0.0, 0.0, 1.0], (3, 1)), model="lambert", ambient=0.2
    )
    cam = cam or rb.Cam("perspective", {"eye": (0, 0, 3), "near": 0.5, "far": 10})
    return rb.Spec([obj], [rb.Light("directional", {"direction": (0, 0, -1)})], cam)


@pytest.mark.parametrize(
    ("what", "tri"),
    [
        ("behind the camera", [[-1, -1, 4], [1, -1, 4], [0, 1, 4]]),
        ("beyond the far plane", [[-50, -50, -20], [50, -50, -20], [0, 50, -20]]),
        ("off screen to the right", [[5, -1, 0], [8, -1, 0], [6, 1, 0]]),
        ("between the eye and the near plane", [[-0.1, -0.1, 2.8], [0.1, -0.1, 2.8], [0, 0.1, 2.8]]),
    ],
)
def test_invisible_triangles_draw_nothing(what: str, tri: Any) -> None:
    spec = one_triangle(tri)
    img = rb.brdfpy_scene(spec).render(rb.brdfpy_camera(spec.camera), 32, 24, outputs="all")
    assert (np.asarray(img.triangle_id) == -1).all(), what
    assert (np.asarray(img.depth) == 1).all() and (np.asarray(img.hdr) == 0).all(), what


@pytest.mark.parametrize(
    "tri",
    [
        [[-1e4, -1, 0], [1e4, -1, 0], [0, 1, 0]],  # far off screen to both sides, crossing it
        [[-0.5, -0.5, 0], [3e3, 0, 0], [-0.5, 0.5, 0]],  # one vertex far to the right
        [[-1e6, -1e6, -1], [1e6, -1e6, -1], [0, 1e6, -1]],  # covers the whole screen
        [[0, 0, 0], [1, 0, 0], [0.5, 0.5, 10]],  # one vertex behind the camera, one beyond the edge
    ],
)
def test_partly_off_screen_triangles_match_reference(tri: Any) -> None:
    spec = one_triangle(tri)
    _img, ref = check_render(spec, 40, 30, "phong")
    assert ref.covered.any()


def test_a_screen_filling_triangle_covers_every_pixel() -> None:
    spec = one_triangle([[-1e6, -1e6, -1], [1e6, -1e6, -1], [0, 1e6, -1]])
    img = rb.brdfpy_scene(spec).render(rb.brdfpy_camera(spec.camera), 57, 31, outputs="all")
    assert (np.asarray(img.triangle_id) == 0).all()


# ----------------------------------------------------------------------------------- outputs


def test_rgb_is_the_clamped_srgb_encoding_of_hdr() -> None:
    spec = canonical(2)
    img = rb.brdfpy_scene(spec).render(rb.brdfpy_camera(spec.camera), 64, 48, outputs="all")
    rgb = np.asarray(img.rgb)
    assert rgb.dtype == np.uint8 and rgb.shape == (48, 64, 3)
    want = otm.to_uint8(np.asarray(img.hdr, dtype=np.float64))
    diff = np.abs(rgb.astype(int) - want.astype(int))
    # float32 sRGB vs float64: a value within rounding of a level boundary may land on the other side
    assert diff.max() <= 1 and (diff > 0).mean() < 0.01


def test_background_depth_and_ids_where_nothing_is_drawn() -> None:
    spec = canonical(2)
    spec.background = (0.25, 0.5, 1.0)
    img = rb.brdfpy_scene(spec).render(rb.brdfpy_camera(spec.camera), 64, 48, outputs="all")
    empty = np.asarray(img.triangle_id) == -1
    assert empty[0, 0] and empty.sum() > 1000
    np.testing.assert_array_equal(
        np.asarray(img.hdr)[empty], np.tile(np.float32([0.25, 0.5, 1.0]), (empty.sum(), 1))
    )
    assert (np.asarray(img.depth)[empty] == 1).all()
    assert (np.asarray(img.depth)[~empty] < 1).all() and (np.asarray(img.depth)[~empty] > 0).all()


def test_supersampling_is_the_box_filtered_finer_render() -> None:
    # samples=4 puts a 2x2 grid of samples in each pixel (at 1/4 and 3/4): exactly the pixel centres of
    # the same view rendered at twice the size, averaged in 2x2 blocks
    spec = canonical(2)
    scene, cam = rb.brdfpy_scene(spec), rb.brdfpy_camera(spec.camera)
    aa = np.asarray(scene.render(cam, 40, 30, samples=4, outputs="all").hdr, dtype=np.float64)
    fine = np.asarray(scene.render(cam, 80, 60, outputs="all").hdr, dtype=np.float64)
    boxed = fine.reshape(30, 2, 40, 2, 3).mean(axis=(1, 3))
    # identical samples up to float32 rounding of the sample positions (and vertex snapping at either
    # resolution: a sample within 1/256 px of an edge may flip, changing its pixel by up to 1/4 of the
    # contrast across the edge; at most a few such pixels)
    close = np.isclose(aa, boxed, rtol=1e-4, atol=1e-5).all(axis=-1)
    assert (~close).sum() <= 3, np.argwhere(~close)[:5]


def test_save_writes_the_rgb_image_as_png(tmp_path: Any) -> None:
    from PIL import Image as PILImage

    spec = canonical(2)
    img = rb.brdfpy_scene(spec).render(rb.brdfpy_camera(spec.camera), 40, 30, outputs="all")
    path = tmp_path / "out.png"
    img.save(path)
    with PILImage.open(path) as f:
        assert f.mode == "RGB" and f.size == (40, 30)
        np.testing.assert_array_equal(np.asarray(f), img.rgb)
    assert img._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("seed", range(3))
def test_overlapping_and_intersecting_triangle_soup_matches_reference(seed: int) -> None:
    # random triangles in a box, many overlapping and piercing each other: the depth test decides each
    # pixel (intersection lines are where the depth gap vanishes, which the reference flags)
    rng = np.random.default_rng(seed)
    centres = rng.uniform(-1, 1, (40, 1, 3))
    v = (centres + rng.normal(scale=0.5, size=(40, 3, 3))).reshape(-1, 3)
    f = np.arange(120).reshape(40, 3)
    n = np.repeat(og._unit_rows(og.face_cross(v, f)), 3, axis=0)
    obj = rb.Obj(v, f, n, model="lambert", params={"kd": 0.7}, ambient=0.1)
    spec = rb.Spec(
        [obj],
        [rb.Light("directional", {"direction": (0.2, -0.3, -1)})],
        rb.Cam("perspective", {"eye": tuple(rng.normal(size=3) * 0.3 + [0, 0, 4]), "fovy": 50}),
    )
    for shading in ("flat", "phong"):
        img, ref = check_render(spec, 64, 48, shading, cull_back_faces=False)
        rb.assert_matches(
            img.depth, ref.depth, img.triangle_id, ref, spec, "depth", rtol=1e-5, buffer="depth"
        )


@pytest.mark.parametrize(
    ("tonemap", "exposure", "white"),
    [("clamp", 1.0, None), ("reinhard", 0.0, None), ("aces", -0.5, None), ("reinhard_extended", 0.0, 3.0)],
)
def test_tone_mapping_operators_and_exposure(tonemap: str, exposure: float, white: float | None) -> None:
    spec = canonical(2)
    scene, cam = rb.brdfpy_scene(spec), rb.brdfpy_camera(spec.camera)
    img = scene.render(cam, 48, 36, tonemap=tonemap, exposure=exposure, white=white, outputs="all")
    x = np.asarray(img.hdr, dtype=np.float64) * 2.0**exposure
    mapped = {
        "clamp": otm.clamp,
        "reinhard": otm.reinhard,
        "aces": otm.aces,
        "reinhard_extended": lambda a: otm.reinhard_extended(a, white),
    }[tonemap](x)
    want = np.floor(255 * otm.srgb_encode(mapped) + 0.5)
    diff = np.abs(np.asarray(img.rgb).astype(int) - want.astype(int))
    assert diff.max() <= 1 and (diff > 0).mean() < 0.02
    # re-mapping a clamp render afterwards gives the same bytes as rendering with that operator
    again = scene.render(cam, 48, 36, outputs="all").tonemapped(tonemap, exposure, white=white)
    np.testing.assert_array_equal(again, img.rgb)


def test_progress_reports_increasing_fractions_and_reraises() -> None:
    spec = canonical(3)
    scene, cam = rb.brdfpy_scene(spec), rb.brdfpy_camera(spec.camera)
    seen: list[float] = []
    scene.render(cam, 256, 192, progress=seen.append, outputs="all")
    assert seen and all(0 <= a < b <= 1 for a, b in zip([0.0, *seen], seen))
    assert seen[-1] == pytest.approx(1.0)

    def fail(_: float) -> None:
        raise KeyError("stop")

    with pytest.raises(KeyError, match="stop"):
        scene.render(cam, 64, 48, progress=fail, outputs="all")
