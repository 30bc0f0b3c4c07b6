"""Sweep specs: a mesh, materials with parameter ranges, a camera turntable and render options, read from a
dict or a JSON file, checked in full, and expanded into render jobs (:func:`brdfpy.distributed.render_many`,
``brdfpy batch``). This module does not import Dask: a spec is validated before any cluster is touched.

A spec (every field optional except ``models``)::

    {
      "mesh": "cow",           # a built-in mesh, "icosphere:4", "torus", "cube", or an OBJ/PLY path
      "floor": true,
      "models": [
        {"name": "cook_torrance",
         "params": {"roughness": {"range": [0.05, 0.6], "steps": 4},
                    "kd": [0.5, 0.12, 0.08],
                    "metal": {"values": ["none", "au"]}}}
      ],
      "camera": {"frames": 12, "elevation": 20, "fovy": 40},
      "size": [640, 480], "shading": "phong", "samples": 1, "ao": false, "shadows": true,
      "formats": ["png"]
    }

The README ("Batches on a Dask cluster") has the table of every field.
"""

from __future__ import annotations

import itertools
import json
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from brdfpy.camera import Camera
from brdfpy.lights import DirectionalLight, Light, PointLight, SpotLight
from brdfpy.mesh import BUILTIN_MESHES, Mesh, builtin_mesh, cube, icosphere, load_mesh, plane, torus
from brdfpy.models import Model, model, model_info, models
from brdfpy.scene import SHADING_MODES, TONEMAPS, Scene
from brdfpy.transforms import scale, translate

__all__ = ["FORMATS", "SPEC_FIELDS", "SpecError", "Sweep", "SweepJob", "load_spec"]

#: File formats a frame can be written in: 8-bit PNG (always possible), OpenEXR half-float HDR (needs the
#: ``OpenEXR`` package on the workers), NumPy ``.npz`` of every rendered buffer.
FORMATS = ("png", "exr", "npz")

#: Every top-level field of a spec and its default.
SPEC_FIELDS: dict[str, Any] = {
    "mesh": "icosphere:4",
    "floor": True,
    "models": None,
    "lights": None,
    "ambient_light": 0.1,
    "background": 0.02,
    "camera": {},
    "size": [640, 480],
    "shading": "phong",
    "samples": 1,
    "ao": False,
    "shadows": True,
    "tonemap": "clamp",
    "exposure": 0.0,
    "formats": ["png"],
    "contact_sheet": {},
    "name": "sweep",
}

CAMERA_FIELDS: dict[str, Any] = {"frames": 1, "elevation": 20.0, "azimuth": 0.0, "fovy": 40.0, "margin": 1.1}
SHEET_FIELDS: dict[str, Any] = {"thumb": 160, "columns": 8}
MAX_JOBS = 1_000_000


class SpecError(ValueError):
    """A sweep spec that cannot be rendered; the message names the field (e.g. ``models[1].params.kd``)."""


@dataclass(frozen=True)
class SweepJob:
    """One frame of a sweep: its ``name``, the material (``material`` index into :attr:`Sweep.materials`),
    the turntable ``frame`` and what the manifest records (``params``)."""

    name: str
    material: int
    frame: int
    camera: Camera
    params: dict[str, Any]


@dataclass
class Sweep:
    """A checked spec: the scene (with the first instance's material to be replaced per job), the
    materials, the jobs and the render options every job shares."""

    spec: dict[str, Any]
    scene: Scene
    materials: list[Model]
    material_labels: list[str]
    jobs: list[SweepJob]
    options: dict[str, Any]
    formats: tuple[str, ...]
    frames: int
    sheet: dict[str, int] = field(default_factory=dict)


def _fail(where: str, problem: str) -> SpecError:
    return SpecError(f"{where}: {problem}")


def _number(where: str, x: Any, lo: float = -math.inf, hi: float = math.inf) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise _fail(where, f"expected a number, got {json.dumps(x)}")
    v = float(x)
    if not (math.isfinite(v) and lo <= v <= hi):
        raise _fail(where, f"must be a finite number in [{lo:g}, {hi:g}], got {x!r}")
    return v


def _integer(where: str, x: Any, lo: int, hi: int) -> int:
    if isinstance(x, bool) or not isinstance(x, int):
        raise _fail(where, f"expected an integer, got {json.dumps(x)}")
    if not lo <= x <= hi:
        raise _fail(where, f"must be an integer in [{lo}, {hi}], got {x}")
    return x


def _bool(where: str, x: Any) -> bool:
    if not isinstance(x, bool):
        raise _fail(where, f"expected true or false, got {json.dumps(x)}")
    return x


def _fields(where: str, d: Any, known: Mapping[str, Any]) -> dict[str, Any]:
    if not isinstance(d, Mapping):
        raise _fail(where, f"expected an object, got {json.dumps(d)}")
    unknown = sorted(set(d) - set(known))
    if unknown:
        raise _fail(
            f"{where}.{unknown[0]}" if where else unknown[0], f"unknown field; known: {', '.join(known)}"
        )
    return {**known, **d}


def _values(where: str, spec: Any, kind: str) -> list[Any]:
    """The values a parameter takes: one value, ``{"values": [...]}`` or ``{"range": [a, b], "steps": k,
    "log": false}`` (``k`` values from ``a`` to ``b`` inclusive, evenly or geometrically spaced)."""
    if isinstance(spec, Mapping):
        keys = set(spec)
        if keys == {"values"}:
            vals = spec["values"]
            if not isinstance(vals, list) or not vals:
                raise _fail(f"{where}.values", "expected a non-empty list")
            return list(vals)
        if "range" in keys and keys <= {"range", "steps", "log"}:
            r = spec["range"]
            if not isinstance(r, list) or len(r) != 2:
                raise _fail(f"{where}.range", f"expected [low, high], got {json.dumps(r)}")
            lo, hi = _number(f"{where}.range[0]", r[0]), _number(f"{where}.range[1]", r[1])
            if lo > hi:
                raise _fail(f"{where}.range", f"low {lo:g} is above high {hi:g}")
            steps = _integer(f"{where}.steps", spec.get("steps", 5), 1, 10_000)
            log = _bool(f"{where}.log", spec.get("log", False))
            if log and lo <= 0:
                raise _fail(f"{where}.range", f"a log range needs low > 0, got {lo:g}")
            if kind not in ("scalar", "color"):
                raise _fail(where, f"a range needs a number parameter, this one is a {kind}")
            xs = np.geomspace(lo, hi, steps) if log else np.linspace(lo, hi, steps)
            return [float(x) for x in xs]
        raise _fail(where, 'expected a value, {"values": [...]} or {"range": [low, high], "steps": N}')
    return [spec]


def _label(name: str, params: Mapping[str, Any]) -> str:
    def fmt(v: Any) -> str:
        if isinstance(v, float):
            return f"{v:.4g}"
        if isinstance(v, (list, tuple)):
            return "(" + ",".join(fmt(x) for x in v) + ")"
        return str(v)

    return " ".join([name] + [f"{k}={fmt(v)}" for k, v in params.items()])


def _materials(spec: Any) -> tuple[list[Model], list[str], list[dict[str, Any]]]:
    if not isinstance(spec, list) or not spec:
        raise _fail("models", 'expected a non-empty list of {"name": ..., "params": {...}}')
    mats: list[Model] = []
    labels: list[str] = []
    combos: list[dict[str, Any]] = []
    known = models()
    for i, entry in enumerate(spec):
        where = f"models[{i}]"
        if isinstance(entry, str):
            entry = {"name": entry}
        e = _fields(where, entry, {"name": None, "params": {}})
        name = e["name"]
        if not isinstance(name, str) or name not in known:
            raise _fail(f"{where}.name", f"unknown model {json.dumps(name)}; known: {', '.join(known)}")
        kinds = {p["name"]: p["kind"] for p in model_info(name)["params"]}
        params = e["params"]
        if not isinstance(params, Mapping):
            raise _fail(f"{where}.params", f"expected an object, got {json.dumps(params)}")
        axes: list[tuple[str, list[Any]]] = []
        for key, value in params.items():
            pw = f"{where}.params.{key}"
            if key not in kinds:
                raise _fail(pw, f"{name} has no parameter {key!r}; its parameters: {', '.join(kinds)}")
            axes.append((key, _values(pw, value, kinds[key])))
        for combo in itertools.product(*(vals for _, vals in axes)):
            p = {k: v for (k, _), v in zip(axes, combo)}
            try:
                mats.append(model(name, **p))
            except (ValueError, TypeError) as err:
                raise _fail(f"{where}.params", f"{err} (values {json.dumps(p)})") from None
            labels.append(_label(name, p))
            combos.append({"model": name, **p})
            if len(mats) > MAX_JOBS:
                raise _fail("models", f"more than {MAX_JOBS} parameter combinations")
    return mats, labels, combos


def _mesh(spec: Any, base: Path | None) -> Mesh:
    if not isinstance(spec, str) or not spec:
        raise _fail("mesh", f"expected a mesh name or a file path, got {json.dumps(spec)}")
    kind, _, arg = spec.partition(":")
    if kind == "icosphere":
        level = 4 if not arg else arg
        if not str(level).isdigit() or not 0 <= int(level) <= 8:
            raise _fail("mesh", f"icosphere level must be an integer in [0, 8], got {arg!r}")
        return icosphere(int(level))
    if spec == "torus":
        return torus(96, 48)
    if spec == "cube":
        return cube()
    if spec in BUILTIN_MESHES:
        return builtin_mesh(spec)
    path = Path(spec)
    if not path.is_absolute() and base is not None:
        path = base / path
    if path.suffix.lower() not in (".obj", ".ply"):
        raise _fail(
            "mesh",
            f"expected icosphere[:LEVEL], torus, cube, {', '.join(BUILTIN_MESHES)} or an .obj/.ply file, "
            f"got {spec!r}",
        )
    if not path.is_file():
        raise _fail("mesh", f"no such file: {str(path)!r}")
    try:
        return load_mesh(path)
    except (ValueError, OSError) as err:
        raise _fail("mesh", str(err)) from None


def _color(where: str, x: Any) -> Any:
    if isinstance(x, (int, float)) and not isinstance(x, bool):
        return _number(where, x, 0.0)
    if isinstance(x, list) and len(x) == 3:
        return [_number(f"{where}[{i}]", c, 0.0) for i, c in enumerate(x)]
    raise _fail(where, f"expected a number or three numbers, got {json.dumps(x)}")


def _vec(where: str, x: Any) -> tuple[float, float, float]:
    if not isinstance(x, list) or len(x) != 3:
        raise _fail(where, f"expected three numbers, got {json.dumps(x)}")
    a, b, c = (_number(f"{where}[{i}]", v) for i, v in enumerate(x))
    return (a, b, c)


def _lights(spec: Any) -> list[Light]:
    if spec is None:
        return [
            DirectionalLight((0.55, -1.0, -0.6), (2.6, 2.3, 2.0)),
            PointLight((4.0, 2.5, 3.5), (14.0, 17.0, 24.0)),
        ]
    if not isinstance(spec, list):
        raise _fail("lights", "expected a list of lights")
    out: list[Light] = []
    for i, entry in enumerate(spec):
        where = f"lights[{i}]"
        if not isinstance(entry, Mapping) or entry.get("type") not in ("directional", "point", "spot"):
            raise _fail(f"{where}.type", 'expected "directional", "point" or "spot"')
        kind = entry["type"]
        try:
            # Every kind takes color and intensity (it emits their product, see brdfpy.lights).
            if kind == "directional":
                e = _fields(
                    where,
                    entry,
                    {"type": None, "direction": [-1, -1, -1], "color": 1.0, "intensity": 1.0},
                )
                out.append(
                    DirectionalLight(
                        _vec(f"{where}.direction", e["direction"]),
                        _color(f"{where}.color", e["color"]),
                        intensity=_color(f"{where}.intensity", e["intensity"]),
                    )
                )
            elif kind == "point":
                e = _fields(where, entry, {"type": None, "position": None, "color": 1.0, "intensity": 10.0})
                out.append(
                    PointLight(
                        _vec(f"{where}.position", e["position"]),
                        _color(f"{where}.intensity", e["intensity"]),
                        color=_color(f"{where}.color", e["color"]),
                    )
                )
            else:
                e = _fields(
                    where,
                    entry,
                    {
                        "type": None,
                        "position": None,
                        "direction": None,
                        "color": 1.0,
                        "intensity": 10.0,
                        "inner_angle": 20.0,
                        "outer_angle": 30.0,
                    },
                )
                out.append(
                    SpotLight(
                        _vec(f"{where}.position", e["position"]),
                        _vec(f"{where}.direction", e["direction"]),
                        _color(f"{where}.intensity", e["intensity"]),
                        _number(f"{where}.inner_angle", e["inner_angle"]),
                        _number(f"{where}.outer_angle", e["outer_angle"]),
                        color=_color(f"{where}.color", e["color"]),
                    )
                )
        except (ValueError, TypeError) as err:
            if isinstance(err, SpecError):
                raise
            raise _fail(where, str(err)) from None
    return out


def load_spec(spec: Mapping[str, Any] | str | os.PathLike[str]) -> Sweep:
    """Check a sweep spec in full and expand it; ``spec`` is a dict or the path of a JSON file (mesh paths
    in it are relative to the file's folder).

    Raises
    ------
    SpecError
        (a ``ValueError``) naming the field: unknown fields, an unknown model or parameter, a value out of
        the parameter's range, a bad range, an unreadable mesh, sizes or counts out of range.
    """
    base: Path | None = None
    if isinstance(spec, (str, os.PathLike)):
        path = Path(spec)
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as err:
            raise SpecError(f"spec: cannot read {str(path)!r}: {err.strerror or err}") from None
        try:
            raw = json.loads(text)
        except json.JSONDecodeError as err:
            raise SpecError(f"spec: {path.name} is not valid JSON: {err}") from None
        base = path.resolve().parent
    else:
        raw = spec
    s = _fields("", raw, SPEC_FIELDS)
    if s["models"] is None:
        raise _fail("models", 'is required: a list of {"name": ..., "params": {...}}')
    materials, labels, combos = _materials(s["models"])
    mesh = _mesh(s["mesh"], base)

    size = s["size"]
    if not isinstance(size, list) or len(size) != 2:
        raise _fail("size", f"expected [width, height], got {json.dumps(size)}")
    width, height = _integer("size[0]", size[0], 1, 16384), _integer("size[1]", size[1], 1, 16384)
    if not isinstance(s["shading"], str) or s["shading"] not in SHADING_MODES:
        raise _fail("shading", f"expected one of {', '.join(SHADING_MODES)}, got {json.dumps(s['shading'])}")
    if not isinstance(s["tonemap"], str) or s["tonemap"] not in TONEMAPS:
        raise _fail("tonemap", f"expected one of {', '.join(TONEMAPS)}, got {json.dumps(s['tonemap'])}")
    samples = _integer("samples", s["samples"], 1, 16)
    if samples not in (1, 4, 9, 16):
        raise _fail("samples", f"must be 1, 4, 9 or 16, got {samples}")
    ao = s["ao"]
    if not isinstance(ao, (bool, Mapping)):
        raise _fail("ao", f"expected true, false or an object of options, got {json.dumps(ao)}")
    formats = s["formats"]
    if not isinstance(formats, list) or not formats or any(f not in FORMATS for f in formats):
        raise _fail(
            "formats", f"expected a non-empty list of {', '.join(FORMATS)}, got {json.dumps(formats)}"
        )
    if "png" not in formats:
        formats = ["png", *formats]  # the contact sheet is made of the PNGs
    cam = _fields("camera", s["camera"], CAMERA_FIELDS)
    frames = _integer("camera.frames", cam["frames"], 1, 100_000)
    elevation = _number("camera.elevation", cam["elevation"], -89.0, 89.0)
    azimuth0 = _number("camera.azimuth", cam["azimuth"])
    fovy = _number("camera.fovy", cam["fovy"], 1.0, 170.0)
    margin = _number("camera.margin", cam["margin"], 0.1, 100.0)
    sheet = _fields("contact_sheet", s["contact_sheet"], SHEET_FIELDS)
    sheet_opts = {
        "thumb": _integer("contact_sheet.thumb", sheet["thumb"], 16, 1024),
        "columns": _integer("contact_sheet.columns", sheet["columns"], 1, 256),
    }
    if not isinstance(s["name"], str) or not s["name"].replace("_", "").replace("-", "").isalnum():
        raise _fail("name", f"expected letters, digits, '-' and '_', got {json.dumps(s['name'])}")
    if len(materials) * frames > MAX_JOBS:
        raise _fail("camera.frames", f"{len(materials)} materials x {frames} frames exceed {MAX_JOBS} jobs")

    scene = Scene(
        ambient_light=_color("ambient_light", s["ambient_light"]),
        background=_color("background", s["background"]),
    )
    center, radius = mesh.bounding_sphere()
    xf = scale(1.0 / radius) @ translate(-center)
    lo = float(mesh.transformed(xf).bounds()[0][1])
    xf = (
        translate(0.0, -lo, 0.0) @ xf
    )  # the object fills the unit sphere around (0, -lo, 0), resting on y = 0
    scene.add(mesh, materials[0], xf)  # ambient: the material's white-sky albedo under ambient_light
    if _bool("floor", s["floor"]):
        scene.add(plane(12.0, 16), model("lambert", kd=(0.3, 0.3, 0.32)))
    for light in _lights(s["lights"]):
        scene.add_light(light)
    options: dict[str, Any] = {
        "width": width,
        "height": height,
        "shading": s["shading"],
        "samples": samples,
        "tonemap": s["tonemap"],
        "exposure": _number("exposure", s["exposure"], -64.0, 64.0),
        "ao": ao if isinstance(ao, bool) else dict(ao),
        "shadows": _bool("shadows", s["shadows"]),
    }
    try:
        scene._ao_args(options["ao"])
    except (ValueError, TypeError) as err:
        raise _fail("ao", str(err)) from None

    cameras = []
    for k in range(frames):
        az = math.radians(azimuth0 + 360.0 * k / frames)
        el = math.radians(elevation)
        d = (math.sin(az) * math.cos(el), math.sin(el), math.cos(az) * math.cos(el))
        cameras.append(
            Camera.framing((0.0, -lo, 0.0), 1.0, d, fovy=fovy, aspect=width / height, margin=margin)
        )
    digits_m, digits_f = len(str(len(materials) - 1)), len(str(frames - 1))
    jobs = [
        SweepJob(
            name=f"{s['name']}_m{m:0{digits_m}d}_f{k:0{digits_f}d}",
            material=m,
            frame=k,
            camera=cameras[k],
            params={**combos[m], "frame": k, "azimuth": azimuth0 + 360.0 * k / frames},
        )
        for m in range(len(materials))
        for k in range(frames)
    ]
    return Sweep(
        spec=dict(raw),
        scene=scene,
        materials=materials,
        material_labels=labels,
        jobs=jobs,
        options=options,
        formats=tuple(dict.fromkeys(formats)),
        frames=frames,
        sheet=sheet_opts,
    )
