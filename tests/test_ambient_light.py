"""Scene(ambient_light=...) lights every object through its own material (its white-sky albedo) unless the
object overrides it with scene.add(..., ambient=...), and ao=True then darkens contacts."""

from __future__ import annotations

import brdfpy
import numpy as np
import pytest
from brdfpy.transforms import translate

CAM = brdfpy.Camera.perspective(eye=(0, 0, 3), target=(0, 0, 0), fovy=45)


def centre(img: brdfpy.Image) -> np.ndarray:
    h, w = img.hdr.shape[:2]
    return img.hdr[h // 2, w // 2]


def sphere_alone(material: brdfpy.Model, **add: object) -> brdfpy.Scene:
    scene = brdfpy.Scene(ambient_light=0.2)
    scene.add(brdfpy.icosphere(4), material, **add)
    return scene


def test_the_ambient_light_lights_an_object_given_no_ambient_through_its_albedo() -> None:
    img = sphere_alone(brdfpy.model("lambert", kd=(0.8, 0.4, 0.2))).render(CAM, 64, 64, outputs="hdr")
    # No light source: only the sky, k_a = kd (a Lambert surface's albedo), I_a = 0.2.
    assert np.allclose(centre(img), [0.16, 0.08, 0.04], atol=1e-5)


def test_a_classic_lambert_gets_its_kd_on_the_course_scale() -> None:
    img = sphere_alone(brdfpy.model("lambert_classic", kd=0.5)).render(CAM, 64, 64, outputs="hdr")
    assert np.allclose(centre(img), 0.1, atol=1e-5)


def test_the_render_is_no_longer_the_same_with_and_without_ambient_light() -> None:
    copper = brdfpy.model("cook_torrance", roughness=0.25, metal="cu")
    lit = sphere_alone(copper)
    dark = brdfpy.Scene(ambient_light=0.0)
    dark.add(brdfpy.icosphere(4), copper)
    for s in (lit, dark):
        s.add_light(brdfpy.DirectionalLight(direction=(-1, -1, -1), color=1.0))
    a = lit.render(CAM, 64, 64, outputs="hdr").hdr
    b = dark.render(CAM, 64, 64, outputs="hdr").hdr
    assert not np.array_equal(a, b)
    # The unlit lower-left of the sphere shows copper: red above green above blue, not black.
    unlit = a[44, 20] - b[44, 20]
    assert unlit[0] > unlit[1] > unlit[2] > 0.02, unlit


def test_an_objects_own_ambient_overrides_the_albedo() -> None:
    img = sphere_alone(brdfpy.model("lambert", kd=0.8), ambient=(0.5, 0.0, 0.25)).render(
        CAM, 64, 64, outputs="hdr"
    )
    assert np.allclose(centre(img), [0.1, 0.0, 0.05], atol=1e-6)


def test_without_ambient_light_an_explicit_ambient_is_the_colour_shown_and_the_rest_is_unlit() -> None:
    scene = brdfpy.Scene()
    assert scene.ambient_light is None
    scene.add(brdfpy.icosphere(4), "lambert", ambient=(0.04, 0.02, 0.01))
    scene.add(brdfpy.icosphere(4), "lambert", translate(5, 0, 0))
    img = scene.render(CAM, 64, 64, outputs="hdr")
    assert np.allclose(centre(img), [0.04, 0.02, 0.01], atol=1e-7)
    side = brdfpy.Camera.perspective(eye=(5, 0, 3), target=(5, 0, 0), fovy=45)
    assert np.all(scene.render(side, 32, 32, outputs="hdr").hdr == 0.0)


def test_the_ambient_follows_a_reassigned_material() -> None:
    scene = sphere_alone(brdfpy.model("lambert", kd=0.8))
    inst = scene.instances[0]
    assert inst.ambient is None
    inst.material = brdfpy.model("lambert", kd=0.25)
    assert np.allclose(centre(scene.render(CAM, 64, 64, outputs="hdr")), 0.05, atol=1e-6)


def test_ao_darkens_the_floor_where_the_sphere_touches_it() -> None:
    scene = brdfpy.Scene(ambient_light=1.0)
    scene.add(brdfpy.icosphere(4), "lambert")
    scene.add(brdfpy.plane(8.0, 96), "lambert", translate(0, -1, 0))
    cam = brdfpy.Camera.perspective(eye=(0, 0.8, 3.6), target=(0, -0.2, 0), fovy=45)
    plain = scene.render(cam, 128, 96, outputs=("hdr", "triangle_id"))
    ao = scene.render(cam, 128, 96, ao=True, outputs=("hdr", "triangle_id"))
    floor = plain.triangle_id >= scene.instances[0].mesh.n_faces
    # Without occlusion the white floor under a white sky shows I_a·albedo = 0.8 everywhere.
    assert np.allclose(plain.hdr[floor], 0.8, atol=1e-5)
    # With it, the floor next to the contact is much darker than the open floor far from it.
    lum = ao.hdr[..., 1]
    below = floor & (np.abs(np.arange(128) - 64) < 6)[None, :]
    contact = lum[below].min()
    open_floor = np.percentile(lum[floor], 95)
    assert contact < 0.6 * open_floor, (contact, open_floor)


def test_bad_ambient_light_is_refused_naming_it() -> None:
    with pytest.raises(ValueError, match="ambient_light"):
        brdfpy.Scene(ambient_light=-1.0)
    with pytest.raises(ValueError, match="ambient_light"):
        brdfpy.Scene(ambient_light=float("nan"))
    with pytest.raises(ValueError, match="ambient"):
        brdfpy.Scene().add(brdfpy.icosphere(1), ambient=(1.0, -0.5, 0.0))
