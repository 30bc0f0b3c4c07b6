"""One convention for every light: each kind takes ``color`` and ``intensity`` and emits their product;
every ``direction`` is the direction in which the light travels."""

from __future__ import annotations

import pickle

import brdfpy
import numpy as np
import pytest

AT = (0.0, 0.0, 0.0)  # a point below the lights, on a floor facing +y


def _point(**kw: object) -> brdfpy.PointLight:
    return brdfpy.PointLight((0.0, 2.0, 0.0), attenuation="none", **kw)  # type: ignore[arg-type]


def _spot(**kw: object) -> brdfpy.SpotLight:
    return brdfpy.SpotLight((0.0, 2.0, 0.0), (0.0, -1.0, 0.0), attenuation="none", **kw)  # type: ignore[arg-type]


KINDS = {
    "directional": lambda **kw: brdfpy.DirectionalLight((0.0, -1.0, 0.0), **kw),
    "point": _point,
    "spot": _spot,
}


@pytest.mark.parametrize("kind", KINDS)
def test_every_light_takes_color_and_intensity_and_emits_their_product(kind):
    make = KINDS[kind]
    light = make(color=(1.0, 0.5, 0.25), intensity=4.0)
    assert light.color == (1.0, 0.5, 0.25) and light.intensity == (4.0, 4.0, 4.0)
    assert light.emitted == (4.0, 2.0, 1.0)
    l, e, _ = light.incident(AT)
    assert np.allclose(l, (0, 1, 0)) and e == pytest.approx((4.0, 2.0, 1.0))
    # Colour and intensity are interchangeable factors of what is emitted.
    for same in (
        make(intensity=(4.0, 2.0, 1.0)),
        make(color=(4.0, 2.0, 1.0)),
        make(color=2, intensity=(2, 1, 0.5)),
    ):
        assert same.incident(AT)[1] == e
    # Both default to 1.
    assert make().emitted == (1.0, 1.0, 1.0)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("name", ["color", "intensity"])
def test_a_bad_color_or_intensity_is_refused_naming_it(kind, name):
    for bad in (-1.0, float("nan"), (1.0, 2.0), "red"):
        with pytest.raises((ValueError, TypeError), match=name):
            KINDS[kind](**{name: bad})
    with pytest.raises(ValueError, match="color, intensity"):
        KINDS[kind](color=1e30, intensity=1e30)  # each finite, the product beyond float32


@pytest.mark.parametrize("kind", KINDS)
def test_color_and_intensity_survive_pickling_and_show_in_the_repr(kind):
    light = KINDS[kind](color=(1.0, 0.5, 0.25), intensity=3.0)
    back = pickle.loads(pickle.dumps(light))
    assert (back.color, back.intensity, back.emitted) == (light.color, light.intensity, light.emitted)
    assert back.incident((0.3, 0.0, 0.1)) == light.incident((0.3, 0.0, 0.1))
    text = repr(light)
    assert "color=(1.0, 0.5, 0.25)" in text and "intensity=(3.0, 3.0, 3.0)" in text


def _floor_render(light: brdfpy.Light) -> np.ndarray:
    scene = brdfpy.Scene(ambient_light=0.0)
    scene.add(brdfpy.plane(4.0, 4), brdfpy.model("lambert", kd=0.5))
    scene.add_light(light)
    cam = brdfpy.Camera.perspective((0.0, 3.0, 0.0), (0.0, 0.0, 0.0), up=(0.0, 0.0, -1.0), fovy=40.0)
    return scene.render(cam, 32, 32, outputs="hdr").hdr


@pytest.mark.parametrize("kind", KINDS)
def test_direction_is_the_direction_of_travel_for_every_light(kind):
    # Every light above the floor points down (0, -1, 0): the floor is lit. Pointing up, it is dark.
    down = _floor_render(KINDS[kind]())
    assert down[16, 16].min() > 0.05
    if kind == "point":
        return
    up = (
        brdfpy.DirectionalLight((0.0, 1.0, 0.0))
        if kind == "directional"
        else brdfpy.SpotLight((0.0, 2.0, 0.0), (0.0, 1.0, 0.0), attenuation="none")
    )
    assert _floor_render(up).max() == 0.0


@pytest.mark.parametrize("kind", KINDS)
def test_a_colored_light_renders_what_it_emits(kind):
    make = KINDS[kind]
    red = _floor_render(make(color=(1.0, 0.0, 0.0), intensity=2.0))
    assert red[..., 1:].max() == 0.0 and red[16, 16, 0] > 0.1
    # color 1 x intensity 2 == color 2 x intensity 1, to the bit.
    assert np.array_equal(_floor_render(make(intensity=2.0)), _floor_render(make(color=2.0)))


def test_the_base_class_is_not_a_light_by_itself():
    with pytest.raises(TypeError, match="DirectionalLight, PointLight, SpotLight, SphereLight or RectLight"):
        brdfpy.Light()
