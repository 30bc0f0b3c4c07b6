"""Renders are bit-identical whatever the number of threads (RASTER.md: tiles are independent and
triangles are rasterized in submission order within a tile; no order-dependent float reductions)."""

from __future__ import annotations

from typing import Any

import brdfpy
import numpy as np
import pytest

from raster_oracle import geometry as og


def canonical_scene() -> brdfpy.Scene:
    kd = np.array([0.8, 0.3, 0.2])
    scene = brdfpy.Scene()
    scene.add(
        brdfpy.icosphere(5),
        brdfpy.model("blinn_phong_classic", kd=tuple(kd), ks=0.5, shininess=32),
        ambient=tuple(0.05 * kd),
    )
    scene.add_light(brdfpy.DirectionalLight((-1, -1, -1), 1.0))
    scene.add_light(brdfpy.PointLight((2, 2, 2), 10.0, attenuation="inverse_square"))
    return scene


def busy_scene() -> brdfpy.Scene:
    # overlapping instances (depth test across tiles and instances), every light kind, a physical model
    scene = brdfpy.Scene(ambient_light=0.2, background=(0.1, 0.1, 0.2))
    ct = brdfpy.model("cook_torrance", kd=0.2, roughness=0.2)
    for i in range(5):
        xf = og.translation((0.4 * i - 0.8, 0.1 * i, -0.3 * i)) @ og.rotation((1, 1, 0), 0.7 * i)
        scene.add(brdfpy.torus(48, 24), ct, xf, ambient=0.05)
    scene.add(brdfpy.plane(6.0, 8), "lambert", og.translation((0, -1, 0)))
    scene.add_light(brdfpy.DirectionalLight((0.2, -1, -0.4), (1.0, 0.9, 0.8)))
    scene.add_light(brdfpy.PointLight((-1, 1.5, 1.5), 5.0, attenuation=(1, 0.2, 0.1)))
    scene.add_light(brdfpy.SpotLight((1, 2, 2), (-0.4, -0.8, -0.8), 10.0, inner_angle=15, outer_angle=30))
    return scene


CASES: list[tuple[str, Any, dict[str, Any]]] = [
    ("canonical phong", canonical_scene, {"shading": "phong"}),
    ("busy gouraud", busy_scene, {"shading": "gouraud"}),
    ("busy quadratic ssaa", busy_scene, {"shading": "quadratic", "samples": 4}),
    ("busy flat reinhard", busy_scene, {"shading": "flat", "tonemap": "reinhard", "exposure": 0.5}),
    ("busy shadows vertex ao", busy_scene, {"shadows": True, "ao": {"samples": 16}}),
    ("busy pixel ao combined", busy_scene, {"ao": {"samples": 8, "per_pixel": True, "combined": True}}),
]


@pytest.mark.parametrize(("what", "build", "options"), CASES, ids=[c[0] for c in CASES])
def test_render_is_bit_identical_across_thread_counts(
    what: str, build: Any, options: dict[str, Any], restore_threads: None
) -> None:
    scene = build()
    cam = brdfpy.Camera.perspective((0.3, 0.8, 3.5), (0, 0, 0), fovy=50)
    outs = {}
    for n in (1, 2, 4):
        brdfpy.set_num_threads(n)
        img = scene.render(cam, 320, 200, outputs="all", **options)
        outs[n] = {k: np.array(getattr(img, k)) for k in ("hdr", "rgb", "depth", "normal", "triangle_id")}
    assert (outs[1]["triangle_id"] >= 0).sum() > 10_000, what
    for n in (2, 4):
        for k, a in outs[1].items():
            # bit-identical: compare the bytes, not the values (NaN != NaN, -0.0 == 0.0)
            assert a.tobytes() == outs[n][k].tobytes(), f"{what}: {k} differs between 1 and {n} threads"


def test_a_render_does_not_depend_on_the_frames_rendered_before_it() -> None:
    # brdfpy draws a new render into the buffers of the last image Python dropped (no fresh pages per
    # frame): nothing of that image may show through, whatever its size, scene, shading or outputs.
    cam = brdfpy.Camera.perspective((0.3, 0.8, 3.5), (0, 0, 0), fovy=50)

    def buffers(img: brdfpy.Image) -> dict[str, bytes]:
        return {k: np.array(getattr(img, k)).tobytes() for k in img.outputs}

    first = buffers(canonical_scene().render(cam, 200, 120, outputs="all"))
    assert set(first) == {"hdr", "rgb", "depth", "normal", "triangle_id"}
    for scene, size, options in [
        (busy_scene(), (320, 200), {"shading": "flat"}),  # larger, every pixel covered differently
        (busy_scene(), (64, 40), {"samples": 4}),  # smaller, supersampled
        (busy_scene(), (200, 120), {"shading": "gouraud"}),  # same size, other content
        (busy_scene(), (200, 120), {"outputs": ("normal",)}),  # other buffers only
        (busy_scene(), (200, 120), {"outputs": ("hdr", "triangle_id"), "samples": 9}),
    ]:
        options = {"outputs": "all", **options}
        img = scene.render(cam, *size, **options)
        kept = buffers(img)
        del img  # its frame becomes the spare the next render draws into
        assert buffers(canonical_scene().render(cam, 200, 120, outputs="all")) == first
        # a render asking for fewer buffers gets exactly those, with the same bits
        few = canonical_scene().render(cam, 200, 120, outputs=("rgb", "depth"))
        assert few.outputs == ("rgb", "depth")
        assert buffers(few) == {k: first[k] for k in ("rgb", "depth")}
        del few
        # and an image keeps its own pixels while later renders run
        held = scene.render(cam, *size, **options)
        canonical_scene().render(cam, 200, 120, outputs="all")
        assert buffers(held) == kept


@pytest.mark.parametrize(("tonemap", "exposure"), [("clamp", 0.0), ("reinhard", 1.0), ("aces", -0.5)])
def test_the_image_encoded_during_the_render_equals_one_encoded_afterwards(
    tonemap: str, exposure: float
) -> None:
    # Scene.render encodes Image.rgb band by band while rendering; Image.tonemapped encodes the HDR buffer
    # afterwards. Same bytes.
    cam = brdfpy.Camera.perspective((0.3, 0.8, 3.5), (0, 0, 0), fovy=50)
    during = busy_scene().render(cam, 160, 100, tonemap=tonemap, exposure=exposure, outputs=("rgb", "hdr"))
    after = busy_scene().render(cam, 160, 100, outputs=("hdr",))
    assert np.array_equal(during.rgb, after.tonemapped(tonemap, exposure))
    assert np.array_equal(during.rgb, during.tonemapped(tonemap, exposure))
