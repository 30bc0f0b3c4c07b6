"""The one module of ``raster_oracle`` that knows brdfpy: it builds the SAME scene for brdfpy's renderer
and for the reference from one plain description, and compares the results. The reference itself
(every other module here) imports nothing from brdfpy.

Tolerances of :func:`compare` (brdfpy renders in float32 with vertex positions snapped to 1/256 px;
the reference in float64, snapped the same way):

* ``edge_eps = 1/128`` px: a float32 screen position can round to the neighbouring 1/256 step of the
  float64 one (and a renderer may truncate instead of rounding), moving an edge by up to 1/256 px;
  pixel centres closer than twice that to an edge of a visible triangle may be decided either way.
  Those pixels are left out of the colour comparison; every pixel whose triangle differs must be one
  of them, and they must stay rare (so the comparison compares something).
* ``rtol = 2e-3``: float32 evaluation of transforms, barycentrics and a BRDF is good to ~1e-6 relative;
  the largest amplification in these scenes is a specular power of up to 64 (x64 -> ~1e-4). 2e-3 is
  an order above that and an order below a formula slip (a wrong constant moves values by > 1 %).
* ``atol = 1e-4 * max``: for pixels whose value is near 0 (unlit, past a cone), where relative error
  means nothing.
* ``+ sensitivity``: that 1/256 px difference in where a vertex lands moves the barycentrics, and with
  them everything interpolated, by an amount that depends on the triangle (a sliver at a silhouette
  is far more sensitive than a large triangle, and a triangle smaller than a pixel most of all). It is
  measured, not guessed: the reference is rendered again ``JITTER_RUNS = 3`` times with every screen
  vertex moved by a uniform random offset of up to ``JITTER = 1/128`` px (twice the possible rounding
  difference) in x and y, and twice each pixel's largest change (a random offset need not point the
  most sensitive way) is added to its tolerance. An interpolation slip (affine instead of
  perspective-correct, a wrong normal) changes values by a sizeable fraction of the variation across a
  whole triangle -- far above this.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import brdfpy
import numpy as np
from numpy.typing import NDArray

from raster_oracle import camera as ocam
from raster_oracle import lights as olights
from raster_oracle import raster as oraster

F64 = NDArray[np.float64]

EDGE_EPS = 1 / 128
RTOL = 2e-3
ATOL_REL = 1e-4
JITTER = 1 / 128
JITTER_RUNS = 3
#: the measured sensitivity is multiplied by this (a random jitter is not the worst-case direction)
SENS_FACTOR = 2.0
#: At least this fraction of the covered pixels must be compared (not near an edge), so that a
#: comparison cannot pass by comparing nothing. Pixels within 1/128 px of an edge are a fraction
#: ~ (edge length per pixel) x 2/128 of the image: a few % even for triangles of one or two pixels.
MIN_COMPARED = 0.8


@dataclass
class Obj:
    """One instance: geometry, a registry model and its parameters, ka, emission, 4x4 transform."""

    vertices: Any
    faces: Any
    normals: Any = None
    model: str = "lambert"
    params: dict[str, Any] = field(default_factory=dict)
    ambient: Any = 0.0
    emission: Any = 0.0
    transform: Any = None
    colors: Any = None


@dataclass
class Light:
    """``kind`` "directional" / "point" / "spot" with the keyword arguments of brdfpy's constructor;
    angles of spot lights in degrees (brdfpy's Python convention)."""

    kind: str
    kw: dict[str, Any]


@dataclass
class Cam:
    kind: str  # "perspective" or "orthographic"
    kw: dict[str, Any]


def brdfpy_camera(c: Cam) -> Any:
    return getattr(brdfpy.Camera, c.kind)(**c.kw)


def oracle_camera(c: Cam) -> ocam.Camera:
    kw = dict(c.kw)
    return getattr(ocam.Camera, c.kind)(**kw)


def _att(a: Any) -> olights.Attenuation:
    if a is None or a == "none":
        return olights.Attenuation("none")
    if isinstance(a, str):
        return olights.Attenuation(a)
    return olights.Attenuation("polynomial", tuple(float(x) for x in a))


def brdfpy_light(light: Light) -> Any:
    cls = {"directional": brdfpy.DirectionalLight, "point": brdfpy.PointLight, "spot": brdfpy.SpotLight}
    return cls[light.kind](**light.kw)


def oracle_light(light: Light) -> Any:
    kw = light.kw
    if light.kind == "directional":
        return olights.Directional(kw["direction"], kw.get("color", 1.0))
    if light.kind == "point":
        return olights.Point(
            kw["position"], kw.get("intensity", 1.0), _att(kw.get("attenuation", "inverse_square"))
        )
    return olights.Spot(
        kw["position"],
        kw["direction"],
        kw.get("intensity", 1.0),
        np.deg2rad(kw["inner_angle"]),
        np.deg2rad(kw["outer_angle"]),
        _att(kw.get("attenuation", "inverse_square")),
    )


@dataclass
class Spec:
    objects: list[Obj]
    lights: list[Light]
    camera: Cam
    ambient_light: Any = 1.0
    background: Any = 0.0


def brdfpy_scene(spec: Spec) -> Any:
    scene = brdfpy.Scene(ambient_light=spec.ambient_light, background=spec.background)
    for o in spec.objects:
        mesh = brdfpy.Mesh(
            np.asarray(o.vertices, np.float32), np.asarray(o.faces, np.uint32), o.normals, colors=o.colors
        )
        kw: dict[str, Any] = {"material": brdfpy.model(o.model, **o.params), "ambient": o.ambient}
        kw["emission"] = o.emission
        if o.transform is not None:
            kw["transform"] = np.asarray(o.transform)
        scene.add(mesh, **kw)
    for light in spec.lights:
        scene.add_light(brdfpy_light(light))
    return scene


def oracle_scene(spec: Spec) -> oraster.Scene:
    """The reference scene, from the float32-rounded geometry brdfpy sees and the model's resolved
    parameters (``brdfpy.model(...).params``: the registry's defaults, not guessed here)."""
    inst = []
    for o in spec.objects:
        v = np.asarray(o.vertices, np.float32).astype(np.float64)
        n = None if o.normals is None else np.asarray(o.normals, np.float32).astype(np.float64)
        params = brdfpy.model(o.model, **o.params).params
        mat = oraster.Material(o.model, params, o.ambient, o.emission)
        t = np.eye(4) if o.transform is None else np.asarray(o.transform, np.float64)
        c = None if o.colors is None else np.asarray(o.colors, np.float32).astype(np.float64)
        inst.append(oraster.Instance(v, np.asarray(o.faces, np.int64), mat, n, t, c))
    return oraster.Scene(inst, [oracle_light(x) for x in spec.lights], spec.ambient_light, spec.background)


def render_both(
    spec: Spec, width: int, height: int, shading: str = "phong", **kw: Any
) -> tuple[Any, oraster.Frame]:
    kw = {"outputs": "all", **kw}  # every buffer is compared with the reference
    img = brdfpy_scene(spec).render(brdfpy_camera(spec.camera), width, height, shading=shading, **kw)
    cull = kw.get("cull_back_faces", True)
    ref = reference(spec, width, height, shading, cull)
    return img, ref


def reference(
    spec: Spec, width: int, height: int, shading: str = "phong", cull: bool = True, **kw: Any
) -> oraster.Frame:
    """The reference frame, with ``sensitivity`` filled in for the hdr, depth and normal buffers: the
    largest change of each pixel over ``JITTER_RUNS`` renders with the screen vertices jittered by up to
    ``JITTER`` px (0 where a jittered render shows another triangle: such pixels are near an edge)."""
    scene, cam = oracle_scene(spec), oracle_camera(spec.camera)
    ref = oraster.render(scene, cam, width, height, shading, cull, **kw)
    rng = np.random.default_rng(12345)
    for _ in range(JITTER_RUNS):
        j = oraster.render(scene, cam, width, height, shading, cull, jitter=(JITTER, rng), **kw)
        same = (j.triangle_id == ref.triangle_id) & (j.instance_id == ref.instance_id)
        for name in ("hdr", "depth", "normal"):
            a, b = getattr(ref, name), getattr(j, name)
            d = np.abs(a - b).reshape(a.shape[0], a.shape[1], -1).max(axis=-1)
            prev = ref.sensitivity.get(name, np.zeros(d.shape))
            ref.sensitivity[name] = np.maximum(prev, np.where(same, d, 0.0))
    return ref


def face_offsets(spec: Spec) -> NDArray[np.int64]:
    """Global triangle id of each instance's face 0 (ids count faces over the instances in order)."""
    return np.concatenate([[0], np.cumsum([len(np.asarray(o.faces).reshape(-1, 3)) for o in spec.objects])])


def global_ids(ref: oraster.Frame, spec: Spec) -> NDArray[np.int64]:
    off = face_offsets(spec)
    return np.where(ref.triangle_id >= 0, off[np.maximum(ref.instance_id, 0)] + ref.triangle_id, -1)


@dataclass
class Comparison:
    agree: NDArray[np.bool_]  # same triangle (or both background) and not ambiguous
    id_mismatch: NDArray[np.bool_]
    ambiguous: NDArray[np.bool_]
    max_excess: float  # max over compared pixels of |got - want| - tol (<= 0 when within tolerance)
    worst: tuple[int, int]


def compare(
    got: Any, want: F64, got_ids: Any, ref: oraster.Frame, spec: Spec, rtol: float = RTOL, buffer: str = "hdr"
) -> Comparison:
    """Compare a brdfpy buffer ``got`` (H, W[, C]) with the reference buffer ``want`` (see module doc)."""
    got = np.asarray(got, dtype=np.float64)
    ids = global_ids(ref, spec)
    gids = np.asarray(got_ids, dtype=np.int64)
    amb = ref.ambiguous(EDGE_EPS)
    mismatch = gids != ids
    agree = ~mismatch & ~amb
    w3 = want.reshape(want.shape[0], want.shape[1], -1)
    g3 = got.reshape(w3.shape)
    scale = float(np.max(np.abs(w3))) if w3.size else 1.0
    sens = ref.sensitivity.get(buffer, np.zeros(ids.shape))
    tol = rtol * np.abs(w3) + ATOL_REL * scale + SENS_FACTOR * sens[..., None]
    excess = np.max(np.abs(g3 - w3) - tol, axis=-1)
    excess = np.where(agree, excess, -np.inf)
    worst = np.unravel_index(int(np.argmax(excess)), excess.shape)
    return Comparison(agree, mismatch, amb, float(excess[worst]), (int(worst[0]), int(worst[1])))


def assert_matches(
    got: Any, want: F64, got_ids: Any, ref: oraster.Frame, spec: Spec, what: str, **kw: Any
) -> None:
    """The full check: triangle ids agree outside ambiguous pixels, the buffer within tolerance there."""
    c = compare(got, want, got_ids, ref, spec, **kw)
    bad = c.id_mismatch & ~c.ambiguous
    if bad.any():
        at = tuple(int(x) for x in np.argwhere(bad)[0])
        raise AssertionError(
            f"{what}: {int(bad.sum())} pixels show a different triangle away from any edge, e.g. (row, col) "
            f"{at}: brdfpy {np.asarray(got_ids)[at]}, reference {global_ids(ref, spec)[at]}"
        )
    covered = max(int(ref.covered.sum()), 1)
    compared = int((c.agree & ref.covered).sum())
    assert compared >= MIN_COMPARED * covered, f"{what}: only {compared} of {covered} covered pixels compared"
    r, col = c.worst
    assert c.max_excess <= 0, (
        f"{what}: pixel (row {r}, col {col}) brdfpy {np.asarray(got)[r, col]} vs reference {want[r, col]} "
        f"(excess over tolerance {c.max_excess:.3g})"
    )
