"""What a render writes (``Scene.render(outputs=...)``) and how large it may be: the image holds the buffers
asked for and says so when another one is read; the size limit is on pixels, whatever the samples per
pixel, stated once (``brdfpy.scene.MAX_PIXELS``, read from the renderer)."""

from __future__ import annotations

import brdfpy
import numpy as np
import pytest
from brdfpy import scene as bscene

CAM = brdfpy.Camera.perspective((0.3, 0.8, 3.5), (0, 0, 0), fovy=50)


def sphere_scene() -> brdfpy.Scene:
    s = brdfpy.Scene(background=(0.02, 0.03, 0.05))
    red = brdfpy.model("blinn_phong_classic", kd=(0.8, 0.3, 0.2), ks=0.5, shininess=32)
    s.add(brdfpy.icosphere(3), red, ambient=(0.04, 0.015, 0.01))
    s.add_light(brdfpy.DirectionalLight((-1, -1, -1)))
    return s


def test_a_plain_render_holds_the_image_and_the_depth_and_names_what_is_missing() -> None:
    img = sphere_scene().render(CAM, 96, 64)
    assert img.outputs == ("rgb", "depth")
    full = sphere_scene().render(CAM, 96, 64, outputs="all")
    assert full.outputs == ("rgb", "hdr", "depth", "normal", "triangle_id")
    assert np.array_equal(img.rgb, full.rgb) and np.array_equal(img.depth, full.depth)
    # The coverage comes from the depth when there are no ids, and agrees with them.
    assert np.array_equal(img.mask, full.mask) and img.covered_pixels == full.covered_pixels > 1000
    for name in ("hdr", "normal", "triangle_id"):
        with pytest.raises(brdfpy.BrdfError, match=f"{name}: not rendered .*outputs including '{name}'"):
            getattr(img, name)
    with pytest.raises(brdfpy.BrdfError, match="needs the 'hdr' output"):
        img.tonemapped("aces")
    # The render's own tone map needs no HDR buffer.
    assert np.array_equal(img.tonemapped("clamp", 0.0), img.rgb)


@pytest.mark.parametrize("samples", [1, 4])
def test_each_output_alone_has_the_bits_of_a_full_render(samples: int) -> None:
    full = sphere_scene().render(CAM, 96, 64, samples=samples, outputs="all")
    for name in bscene.OUTPUTS:
        one = sphere_scene().render(CAM, 96, 64, samples=samples, outputs=name)
        assert one.outputs == (name,)
        assert getattr(one, name).tobytes() == getattr(full, name).tobytes(), name
    # The 8-bit image is there whenever the HDR colours are.
    hdr_only = sphere_scene().render(CAM, 96, 64, samples=samples, outputs=["hdr"])
    assert np.array_equal(hdr_only.rgb, full.rgb)
    assert "outputs hdr" in repr(sphere_scene().render(CAM, 8, 8, outputs=("hdr",)))


def test_bad_outputs_are_refused_naming_the_argument() -> None:
    s = sphere_scene()
    with pytest.raises(ValueError, match="outputs: unknown output 'colour'"):
        s.render(CAM, 8, 8, outputs=("rgb", "colour"))
    with pytest.raises(ValueError, match="outputs: asks for nothing"):
        s.render(CAM, 8, 8, outputs=())
    with pytest.raises(TypeError, match="outputs"):
        s.render(CAM, 8, 8, outputs=3)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="outputs"):
        s.render(CAM, 8, 8, outputs=["rgb", None])  # type: ignore[list-item]


def test_the_size_limit_is_on_pixels_stated_once_and_named_in_the_error() -> None:
    assert (bscene.MAX_IMAGE_SIDE, bscene.MAX_PIXELS) == (16384, 2**26)
    doc = brdfpy.Scene.render.__doc__ or ""
    assert f"{bscene.MAX_PIXELS:,}" in doc and str(bscene.MAX_IMAGE_SIDE) in doc and "<MAX" not in doc
    for samples in (1, 16):
        with pytest.raises(
            ValueError, match=f"width, height: 16384×4097 .* limit of {bscene.MAX_PIXELS} pixels"
        ):
            sphere_scene().render(CAM, 16384, 4097, samples=samples)


def test_4k_at_16_samples_per_pixel_renders() -> None:
    # Refused before ("exceeds the limit of 67108864" samples): supersamples are resolved band by band,
    # so 133 million samples need no more memory than a few bands of them.
    s = sphere_scene()
    big = s.render(CAM, 3840, 2160, samples=16, outputs=("rgb", "depth"))
    assert big.rgb.shape == (2160, 3840, 3)
    one = s.render(CAM, 3840, 2160, samples=1, outputs=("rgb", "depth"))
    # The same sphere: coverage equal up to the silhouette's partly covered pixels, colours alike.
    assert abs(big.covered_pixels - one.covered_pixels) < 0.01 * one.covered_pixels
    inside = one.mask & big.mask
    diff = np.abs(big.rgb[inside].astype(int) - one.rgb[inside].astype(int))
    assert diff.mean() < 0.5 and big.covered_pixels > 1_000_000
