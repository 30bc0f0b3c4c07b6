"""The public API of brdfpy as fuzz targets, and the classification of what each call did.

:func:`targets` enumerates every public function, class and method from the package's ``__all__`` (and
the ``__all__`` of the submodules it lists), so a new public name is fuzzed at once — or, if one of its
parameters has no generator, :func:`missing_generators` names it and ``tests/test_fuzz_api.py`` fails.

:func:`call` draws arguments for one target from a ``random.Random`` (plausible values, each replaced by
a hostile one with some probability, plus now and then an unknown keyword or a missing argument), runs
it, and returns an :class:`Outcome` — ``ok``, ``clean`` (a ``TypeError``/``ValueError``/``OSError``
whose message names the argument and the problem) or ``failure`` (any other exception type, a message
that names nothing, NaN or ∞ out of finite input).
"""

from __future__ import annotations

import inspect
import math
import random
import re
import types
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import brdfpy
import numpy as np

from fuzzing import values as V

# ------------------------------------------------------------------------------------ the call targets


@dataclass(frozen=True)
class Target:
    """One public callable: ``qualname`` (``brdfpy.fresnel.dielectric``, ``brdfpy.Mesh.transformed``),
    how to get it (for a method: from a fresh instance), and its parameters."""

    qualname: str
    get: Callable[[random.Random], Callable[..., Any]]
    params: tuple[inspect.Parameter, ...]
    module: str


#: Public names that are not fuzzed, and why (each a conscious decision, checked to exist).
EXCLUDED: dict[str, str] = {
    "brdfpy.explore": "needs the optional Panel extra and a notebook; covered by tests/test_explorer*.py",
    "brdfpy.set_num_threads": "changes process-wide state that the rest of the run depends on; fuzzed "
    "separately in test_fuzz_api.py with hostile counts",
    "brdfpy.BrdfError": "an exception class",
    "brdfpy.Image.to_pil": "returns a Pillow image; no arguments",
}

#: Containers of data without behaviour (TypedDict / NamedTuple results): their constructors are
#: Python's, not brdfpy's.
DATA_CLASSES = {
    "ModelInfo",
    "ParamInfo",
    "Hits",
    "FitResult",
    "FitReport",
    "ChannelError",
    "Comparison",
    "Quadrature",
    "CheckReport",
    "Chi2Result",
    "AlbedoBySampling",
    "SceneAsset",
    "Coverage",
}


#: Result containers (dataclasses) whose constructor only stores fields: their methods are fuzzed.
RESULT_CLASSES = {"Polar", "Lobe", "HalfDiffSlice", "Albedo", "AlbedoTable"}


def _cube() -> brdfpy.Mesh:
    return brdfpy.cube()


@lru_cache(maxsize=1)
def _image() -> brdfpy.Image:
    s = brdfpy.Scene()
    s.add(brdfpy.cube())
    return s.render(brdfpy.Camera.framing((0, 0, 0), 2.0), width=8, height=6, outputs="all")


@lru_cache(maxsize=1)
def _table() -> Any:
    return brdfpy.measured.Tabulated.from_model(brdfpy.model("lambert"), (3, 3, 4))


def _views_result(kind: str) -> Any:
    m = brdfpy.model("lambert")
    if kind == "Polar":
        return brdfpy.views.polar(m, n=16)
    if kind == "Lobe":
        return brdfpy.views.lobe(m, n_theta=4, n_phi=8)
    if kind == "HalfDiffSlice":
        return brdfpy.views.half_diff_slice(m, size=8)
    if kind == "Albedo":
        return brdfpy.views.albedo(m, theta_i=[0.0, 30.0])
    return brdfpy.views.albedo_table(brdfpy.model("cook_torrance"), values=[0.2, 0.5], theta_i=[0.0, 30.0])


#: A fresh instance of each public class, for its methods (fresh, as some methods change the object).
INSTANCES: dict[str, Callable[[random.Random], Any]] = {
    "Camera": lambda r: (
        brdfpy.Camera() if r.random() < 0.5 else brdfpy.Camera.orthographic((0, 0, 3), (0, 0, 0))
    ),
    "Image": lambda r: _image(),
    "Mesh": lambda r: r.choice(
        [_cube, lambda: brdfpy.icosphere(1), lambda: brdfpy.plane(), _degenerate_mesh]
    )(),
    "Model": lambda r: brdfpy.model(r.choice(brdfpy.models())),
    "Scene": lambda r: _scene(),
    "RayCaster": lambda r: brdfpy.RayCaster(brdfpy.cube()),
    "DirectionalLight": lambda r: brdfpy.DirectionalLight(),
    "PointLight": lambda r: brdfpy.PointLight((0, 2, 0)),
    "SpotLight": lambda r: brdfpy.SpotLight((0, 2, 0), (0, -1, 0)),
    "SphereLight": lambda r: brdfpy.SphereLight((0, 2, 0), 0.3),
    "RectLight": lambda r: brdfpy.RectLight((0, 2, 0), (1, 0, 0), (0, 0, 1), two_sided=r.random() < 0.5),
    # The base class of the area lights cannot be made either.
    "AreaLight": lambda r: r.choice([INSTANCES["SphereLight"], INSTANCES["RectLight"]])(r),
    "Instance": lambda r: _scene().add(brdfpy.cube()),
    # The base class cannot be made: its methods are those of the lights.
    "Light": lambda r: _light(r, False),
    "Tabulated": lambda r: _table(),
    "Polar": lambda r: _views_result("Polar"),
    "Lobe": lambda r: _views_result("Lobe"),
    "HalfDiffSlice": lambda r: _views_result("HalfDiffSlice"),
    "Albedo": lambda r: _views_result("Albedo"),
    "AlbedoTable": lambda r: _views_result("AlbedoTable"),
    "Environment": lambda r: r.choice(
        [lambda: brdfpy.Environment.uniform(0.5), _sky, lambda: brdfpy.Environment(np.ones((2, 4, 3)))]
    )(),
    "Texture": lambda r: _texture(r),
    "TextureChannel": lambda r: _texture(r, 4).channel(r.randrange(4)),
    "TexturedModel": lambda r: brdfpy.model(
        "cook_torrance", kd=_texture(r), roughness=_texture(r, 3).channel(1)
    ),
    "RglBsdf": lambda r: _rgl(),
    "TextureSource": lambda r: r.choice(
        [
            lambda: brdfpy.TextureSource.scaled(_texture(r), r.uniform(0, 2)),
            lambda: brdfpy.TextureSource.squared(_texture(r, 3).channel(1), r.uniform(0, 1)),
            lambda: brdfpy.TextureSource.metallic_diffuse(_texture(r, 3), _texture(r, 3).channel(2)),
            lambda: brdfpy.TextureSource.metallic_f0((0.9, 0.6, 0.3), r.uniform(0, 1)),
        ]
    )(),
    "AnisotropicTabulated": lambda r: _aniso(),
}


@lru_cache(maxsize=1)
def _aniso() -> Any:
    return brdfpy.measured.AnisotropicTabulated.from_model(brdfpy.model("ward"), (2, 2, 3, 4))


def _aniso_values(r: random.Random, h: bool) -> Any:
    """Values of an AnisotropicTabulated: (a, b, c, d, 3) non-negative, or poison, wrong shape or dtype."""
    if not h:
        return np.full((2, 1, 3, 2, 3), 0.1, np.float32)
    return r.choice(
        [
            np.full((2, 2, 2, 2, 3), -1.0),
            np.ones((0, 2, 2, 2, 3)),
            np.ones((2, 2, 2, 2)),
            np.full((1, 1, 1, 1, 3), np.nan),
            V.hostile_other(r),
        ]
    )


def _mit_bytes(r: random.Random, h: bool) -> Any:
    if not h:
        return _aniso().to_bytes()
    good = _aniso().to_bytes()
    return r.choice(
        [
            b"",
            good[:40],
            good[:-1],
            good + b"\x00",
            np.array([4096] * 4 + [0] * 12, "<i4").tobytes(),
            np.array([2, 2, 3, 4, 0, 0, 7, 0, 0, 0, 3, 0, 0, 0, 0, 0], "<i4").tobytes() + good[64:],
            -1,
            10**12,
            V.hostile_other(r),
        ]
    )


def _texture(r: random.Random, channels: int | None = None) -> Any:
    shape = r.choice([(4, 4), (3, 5, 3), (2, 2, 4)]) if channels is None else (3, 5, channels)
    return brdfpy.Texture(
        np.random.default_rng(r.randrange(2**32)).random(shape, dtype=np.float32),
        wrap=r.choice(["repeat", "clamp", "mirror"]),
        filter=r.choice(["nearest", "bilinear", "trilinear"]),
    )


def _uv(r: random.Random, h: bool, scale: float = 2.0) -> Any:
    a = (np.random.default_rng(r.randrange(2**32)).random((r.randint(1, 8), 2)) - 0.25) * scale
    return (
        a.astype(np.float32) if not h else r.choice([a[:, :1], np.full_like(a, np.nan), V.hostile_other(r)])
    )


@lru_cache(maxsize=1)
def _rgl() -> Any:
    return brdfpy.measured.RglBsdf.from_model(
        brdfpy.model("cook_torrance"), n_theta_i=3, n_phi_i=2, grid=(4, 4)
    )


@lru_cache(maxsize=1)
def _sky() -> Any:
    return brdfpy.Environment.sky()


def _scene() -> brdfpy.Scene:
    s = brdfpy.Scene()
    s.add(brdfpy.cube())
    return s


def _degenerate_mesh() -> brdfpy.Mesh:
    # Two triangles with repeated vertices and one of zero area: valid, but every query must cope.
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], np.float32)
    f = np.array([[0, 1, 2], [1, 1, 3], [0, 0, 0]], np.uint32)
    return brdfpy.Mesh(v, f)


def _public_modules() -> list[types.ModuleType]:
    mods = [brdfpy]
    for n in brdfpy.__all__:
        obj = getattr(brdfpy, n)
        if isinstance(obj, types.ModuleType):
            mods.append(obj)
    return mods


def _is_type_alias(obj: Any) -> bool:
    """``Union[...]`` and other typing constructs exported for annotations (``views.ModelLike``)."""
    return type(obj).__module__ == "typing" or type(obj).__name__ in ("UnionType", "GenericAlias")


def _signature(fn: Any) -> tuple[inspect.Parameter, ...] | None:
    try:
        sig = inspect.signature(fn)
    except (TypeError, ValueError):
        return None
    return tuple(p for p in sig.parameters.values() if p.name not in ("self", "cls"))


def public_names() -> list[str]:
    """Every public callable's qualified name: functions and classes of the ``__all__`` lists, and the
    public methods of those classes."""
    return [t.qualname for t in targets()] + sorted(EXCLUDED)


@lru_cache(maxsize=1)
def targets() -> tuple[Target, ...]:
    out: list[Target] = []
    seen: set[str] = set()
    for mod in _public_modules():
        prefix = mod.__name__
        for n in getattr(mod, "__all__", []):
            obj = getattr(mod, n)
            qual = f"{prefix}.{n}"
            if isinstance(obj, types.ModuleType) or qual in EXCLUDED or _is_type_alias(obj):
                continue
            if isinstance(obj, type):
                if obj.__name__ in seen:
                    continue
                seen.add(obj.__name__)
                if issubclass(obj, BaseException) or n in DATA_CLASSES:
                    continue
                _class_targets(obj, qual, prefix, out)
            elif callable(obj):
                params = _signature(obj)
                if params is not None:
                    out.append(Target(qual, (lambda o: lambda r: o)(obj), params, prefix))
    return tuple(out)


def _class_targets(cls: type, qual: str, module: str, out: list[Target]) -> None:
    init = _signature(cls)
    if init is not None and cls.__name__ not in RESULT_CLASSES:
        out.append(Target(qual, lambda r, c=cls: c, init, module))
    for name, attr in sorted(inspect.getmembers(cls)):
        if name.startswith("_") or f"{qual}.{name}" in EXCLUDED:
            continue
        raw = inspect.getattr_static(cls, name, None)
        if isinstance(raw, (property,)) or type(raw).__name__ == "getset_descriptor":
            if isinstance(raw, property) and raw.fset is not None:
                out.append(Target(f"{qual}.{name}=", _setter(cls, name), (_value_param(name),), module))
            continue
        if not callable(attr):
            continue
        params = _signature(attr)
        if params is None:
            continue
        if isinstance(raw, (classmethod, staticmethod)) or type(raw).__name__ in (
            "builtin_function_or_method",
        ):
            out.append(
                Target(f"{qual}.{name}", (lambda c, n: lambda r: getattr(c, n))(cls, name), params, module)
            )
        else:
            out.append(Target(f"{qual}.{name}", _bound(cls, name), params, module))


def _instance(cls: type, r: random.Random) -> Any:
    for klass in cls.__mro__:
        if klass.__name__ in INSTANCES:
            return INSTANCES[klass.__name__](r)
    raise KeyError(f"no instance factory for {cls.__name__}: add one to fuzzing.api.INSTANCES")


def _bound(cls: type, name: str) -> Callable[[random.Random], Callable[..., Any]]:
    return lambda r: getattr(_instance(cls, r), name)


def _setter(cls: type, name: str) -> Callable[[random.Random], Callable[..., Any]]:
    def get(r: random.Random) -> Callable[..., Any]:
        obj = _instance(cls, r)
        return lambda value: setattr(obj, name, value)

    return get


def _value_param(name: str) -> inspect.Parameter:
    return inspect.Parameter("value", inspect.Parameter.POSITIONAL_OR_KEYWORD, annotation=name)


# ------------------------------------------------------------------------- generators per parameter


def _model_like(r: random.Random, hostile: bool) -> Any:
    if hostile:
        return V.name(r, True, [])
    k = r.randrange(3)
    if k == 0:
        return r.choice(brdfpy.models())
    if k == 1:
        return brdfpy.model(r.choice(brdfpy.models()))
    return [brdfpy.model("lambert"), "cook_torrance"]


def _mesh(r: random.Random, hostile: bool) -> Any:
    if not hostile:
        return INSTANCES["Mesh"](r)
    return r.choice(
        [
            lambda: (np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32)),
            lambda: {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "faces": [[0, 1, 5]]},
            lambda: (np.full((3, 3), np.nan, np.float32), np.array([[0, 1, 2]], np.uint32)),
            lambda: "cow",
            lambda: V.hostile_other(r),
        ]
    )()


def _camera(r: random.Random, hostile: bool) -> Any:
    return INSTANCES["Camera"](r) if not hostile else V.hostile_other(r)


def _light(r: random.Random, hostile: bool) -> Any:
    if hostile:
        return V.hostile_other(r)
    kinds = ["DirectionalLight", "PointLight", "SpotLight", "SphereLight", "RectLight"]
    return INSTANCES[r.choice(kinds)](r)


def _matrix(r: random.Random, hostile: bool) -> Any:
    if not hostile:
        return r.choice(
            [
                np.eye(4),
                brdfpy.transforms.rotate((0, 1, 0), r.uniform(-180, 180)),
                brdfpy.transforms.scale(2.0),
            ]
        )
    return r.choice(
        [
            np.zeros((4, 4)),
            np.full((4, 4), np.nan),
            np.eye(3),
            np.eye(4)[::-1],
            np.diag([1e38, 1e38, 1e38, 1.0]),
            np.eye(4, dtype=complex),
            V.hostile_other(r),
        ]
    )


def _callable_f(r: random.Random, hostile: bool) -> Any:
    if not hostile:
        return r.choice([lambda d: d[:, 2], lambda d: np.maximum(d, 0), np.ones(1)])
    return r.choice([lambda d: "x", lambda d: d[:, :1], lambda d: np.full(len(d), np.nan), 3, None])


def _lobes(r: random.Random, hostile: bool) -> Any:
    if not hostile:
        return [(1.0, r.choice(brdfpy.microfacet.DISTRIBUTIONS), r.uniform(0.05, 1.0))]
    return r.choice(
        [
            [],
            [(1.0, "ggx")],
            [(-1.0, "ggx", 0.3)],
            [(1.0, "nope", 0.3)],
            [(math.nan, "ggx", 0.3)],
            [("a", "ggx", 0.3)],
            "ggx",
            V.hostile_other(r),
        ]
    )


def _sampler(r: random.Random, hostile: bool) -> Any:
    m = brdfpy.model("lambert")
    return m.sample if not hostile else r.choice([None, 3, lambda *a, **k: (1, 2), print])


def _pdf(r: random.Random, hostile: bool) -> Any:
    m = brdfpy.model("lambert")
    return m.pdf if not hostile else r.choice([None, 3, lambda *a, **k: "x"])


def _mapping(r: random.Random, hostile: bool) -> Any:
    if not hostile:
        return {"roughness": r.uniform(0.1, 0.9)}
    return r.choice(
        [{}, {"roughness": math.nan}, {"nope": 1.0}, {"roughness": "x"}, ["roughness"], V.hostile_other(r)]
    )


def _resolution(r: random.Random, hostile: bool) -> Any:
    if not hostile:
        return (r.randint(2, 5), r.randint(2, 5), r.randint(2, 8))
    return r.choice(
        [
            (0, 2, 2),
            (1, 1, 1),
            (4096, 4096, 4096),
            (2**31, 2, 2),
            (-1, 2, 2),
            (2, 2),
            (2.5, 2, 2),
            V.hostile_other(r),
        ]
    )


def _size_wh(r: random.Random, hostile: bool) -> Any:
    if not hostile:
        return r.choice([r.randint(2, 12), (r.randint(2, 12), r.randint(2, 12))])
    return r.choice([0, -1, 10**9, (0, 4), (4, 10**9), (2**31, 2**31), 2.5, V.hostile_other(r)])


def _quadrature_triple(r: random.Random, hostile: bool) -> Any:
    if not hostile:
        return r.choice([None, (4, 4, 1e-3)])
    return r.choice([(0, 4, 1e-3), (10**9, 4, 1e-3), (4, 4, -1.0), (4,), V.hostile_other(r)])


def _quad(r: random.Random, hostile: bool) -> Any:
    if not hostile:
        return r.choice([None, brdfpy.sh.quadrature(4)])
    d = np.ones((3, 3))
    return r.choice(
        [
            brdfpy.sh.Quadrature(d, np.ones(2)),
            brdfpy.sh.Quadrature(d * np.nan, np.ones(3)),
            3,
            V.hostile_other(r),
        ]
    )


def _env_image(r: random.Random, hostile: bool) -> Any:
    """An (H, W, 3) radiance map: small and non-negative, or with poison, wrong shape or dtype."""
    h, w = r.randint(1, 4), r.randint(2, 8)  # (drawn once: a list of rows of several widths is ragged)
    a = np.asarray(
        [[[r.uniform(0.0, 2.0) for _ in range(3)] for _ in range(w)] for _ in range(h)], np.float32
    )
    if not hostile:
        return a
    k = r.randrange(5)
    if k == 0:
        return V._poison(r, a.copy())
    if k == 1:
        return V._cast(r, a)
    if k == 2:
        return a[..., :2] if r.random() < 0.5 else a[0]
    if k == 3:
        return -a
    return V.hostile_other(r)


def _environment(r: random.Random, hostile: bool) -> Any:
    if not hostile:
        return None if r.random() < 0.3 else INSTANCES["Environment"](r)
    return V.hostile_other(r)


def _channels(lo: float, hi: float) -> V.Generator:
    def gen(r: random.Random, hostile: bool) -> Any:
        if not hostile:
            return r.choice([r.uniform(lo, hi), [r.uniform(lo, hi) for _ in range(3)]])
        return r.choice([[1.0, 2.0], [math.nan] * 3, -1.0, V.hostile_other(r), r.choice(V.HOSTILE_FLOATS)])

    return gen


def _f(lo: float, hi: float, log: bool = False) -> V.Generator:
    return lambda r, h: V.number(r, h, lo, hi, log)


def _i(lo: int, hi: int) -> V.Generator:
    return lambda r, h: V.integer(r, h, lo, hi)


def _opt(gen: V.Generator) -> V.Generator:
    return lambda r, h: None if (not h and r.random() < 0.3) else gen(r, h)


def _names(choices: Callable[[], list[str]]) -> V.Generator:
    return lambda r, h: V.name(r, h, list(choices()))


_vec = V.vec3
_sc = V.scalars

#: Generator of each parameter name (the project uses one name per concept; README "Names").
PARAMS: dict[str, V.Generator] = {
    # directions and points
    **{
        k: _vec
        for k in (
            "l",
            "v",
            "n",
            "h",
            "w",
            "tangent",
            "direction",
            "directions",
            "p",
            "position",
            "eye",
            "target",
            "up",
            "axis",
            "center",
            "points",
            "origins",
            "peak",
            "light",
            "offset",
        )
    },
    "tangent_axis": _opt(_vec),
    # measured: anisotropic tables and the MIT CSAIL .dat format
    "dims": lambda r, h: (
        tuple(r.randint(1, 4) for _ in range(4))
        if not h
        else r.choice([(0, 2, 2, 2), (2, 2, 2), (4096, 4096, 4096, 4096), (2, -1, 2, 2), V.hostile_other(r)])
    ),
    "half_data": V.bools,
    "scale": _f(0.5, 20.0),
    "valid": lambda r, h: (
        None if not h else r.choice([np.ones((2, 2), bool), np.ones(3), V.hostile_other(r)])
    ),
    # arrays of numbers
    "cos_i": _sc,
    "x": _sc,
    "values": lambda r, h: _sc(r, h, 0.0, 2.0),
    "theta": lambda r, h: _sc(r, h, 0.0, 90.0),
    "phi": lambda r, h: _sc(r, h, 0.0, 360.0),
    "cos_theta_v": lambda r, h: _sc(r, h, 0.05, 1.0),
    "theta_i": _opt(lambda r, h: _sc(r, h, 0.0, 89.0)),
    "u": _opt(lambda r, h: _sc(r, h, 0.0, 0.999)),
    "coeffs": lambda r, h: _sc(r, h, -1.0, 1.0),
    "kernel": lambda r, h: _sc(r, h, 0.0, 1.0),
    "radiance": lambda r, h: _sc(r, h, 0.0, 1.0),
    "vertices": _vec,
    "normals": _opt(_vec),
    "colors": _opt(_vec),
    "faces": lambda r, h: (
        np.array([[0, 1, 2]], np.uint32)
        if not h
        else r.choice(
            [
                np.array([[0, 1, 9]]),
                np.array([[-1, 0, 1]]),
                np.array([[0, 1]]),
                np.zeros((0, 3), np.int64),
                V.hostile_other(r),
            ]
        )
    ),
    "matrix": _matrix,
    "transform": _opt(_matrix),
    "table": lambda r, h: (
        np.full((2, 3, 4, 3), 0.1, np.float32)
        if not h
        else r.choice(
            [
                np.full((2, 2, 2, 3), -1.0),
                np.ones((1, 2, 2, 3)),
                np.ones((2, 2, 2)),
                np.full((2, 2, 2, 3), np.nan),
                V.hostile_other(r),
            ]
        )
    ),
    "data": lambda r, h: (
        _table().to_merl_bytes()
        if not h
        else r.choice(
            [b"", b"\x00" * 12, bytes(np.array([4096] * 3, "<i4").tobytes()), -1, 10**12, V.hostile_other(r)]
        )
    ),
    # numbers
    "alpha": _f(0.01, 1.0),
    "alpha_y": _opt(_f(0.01, 1.0)),
    "eta": _channels(1.0, 2.5),
    "k": _channels(0.0, 4.0),
    "f0": _channels(0.0, 1.0),
    "f0_ref": _opt(_f(0.0, 1.0)),
    "ev": _f(-4.0, 4.0),
    "exposure": _f(-4.0, 4.0),
    "white": _opt(_f(0.5, 8.0)),
    "tau": _f(0.1, 8.0),
    "d_max": _opt(_f(0.1, 4.0)),
    "radius": lambda r, h: _f(0.1, 5.0)(r, h) if r.random() < 0.8 else V.name(r, h, ["f", "f_cos"]),
    "fovy": _f(10.0, 120.0),
    "near": _f(0.01, 1.0),
    "far": _f(5.0, 100.0),
    "aspect": _f(0.5, 2.0),
    "lights": _names(lambda: ["auto", "file", "default", "none"]),
    "margin": _f(1.0, 1.5),
    "degrees": lambda r, h: V.number(r, h, -360, 360) if r.random() < 0.8 else bool(r.random() < 0.5),
    "intensity": _channels(0.0, 4.0),
    "color": _channels(0.0, 1.0),
    "ambient": _channels(0.0, 1.0),
    "emission": _channels(0.0, 1.0),
    "inner_angle": _f(5.0, 30.0),
    "outer_angle": _f(31.0, 60.0),
    "zoom": _f(1.0, 4.0),
    "significance": _f(1e-3, 0.1),
    "min_panel": _f(1e-5, 1e-2),
    "size": lambda r, h: _f(0.5, 3.0)(r, h) if r.random() < 0.5 else _size_wh(r, h),
    "phi_d": _f(0.0, 180.0),
    "t_min": _f(0.0, 0.1),
    "t_max": _f(1.0, 100.0),
    "delay": _f(0.0, 1.0),
    "sx": _f(0.5, 2.0),
    "sy": _opt(_f(0.5, 2.0)),
    "sz": _opt(_f(0.5, 2.0)),
    "y": _opt(_f(-2.0, 2.0)),
    "z": _opt(_f(-2.0, 2.0)),
    "a": _sc,
    "value": _sc,
    # integers
    "count": _i(1, 64),
    "samples": _i(1, 64),
    "seed": _i(0, 2**32),
    "order": _i(0, 6),
    "n_mu": _opt(_i(1, 16)),
    "n_phi": _i(1, 16),
    "n_theta": _i(1, 16),
    "width": _i(1, 16),
    "height": _i(1, 16),
    "level": _i(0, 3),
    "subdivisions": _i(1, 3),
    "major_segments": _i(3, 16),
    "minor_segments": _i(3, 16),
    "sample_count": _i(100, 5000),
    "n_samples": _i(16, 2048),
    "test_count": _i(1, 2),
    "ires": _i(1, 4),
    "max_iterations": _i(1, 20),
    "m": _i(-3, 3),
    "resolution": _resolution,
    "quadrature": _quadrature_triple,
    "quad": _quad,
    # names
    "name": _names(lambda: brdfpy.models() + list(brdfpy.BUILTIN_MESHES) + list(brdfpy.fresnel.METALS)),
    "model_name": _names(brdfpy.models),
    "distribution": lambda r, h: (
        _names(lambda: list(brdfpy.microfacet.DISTRIBUTIONS))(r, h) if r.random() < 0.8 else _lobes(r, h)
    ),
    "masking": _names(lambda: list(brdfpy.microfacet.MASKINGS)),
    "operator": _names(lambda: list(brdfpy.tonemap.OPERATORS)),
    "tonemap": _names(lambda: list(brdfpy.tonemap.OPERATORS)),
    "shading": _names(lambda: ["flat", "gouraud", "phong"]),
    "weighting": _names(lambda: ["angle", "area", "equal"]),
    "method": _names(lambda: ["newell", "cross"]),
    "attenuation": _names(lambda: ["inverse_square", "none", "linear"]),
    "channel": _names(lambda: ["luminance", "r", "g", "b"]),
    "format": _opt(_names(lambda: ["PNG", "png", "JPEG", "BMP"])),
    "label": _names(lambda: ["rendering"]),
    "param": _names(lambda: ["roughness", "kd", "shininess"]),
    "outputs": lambda r, h: (
        V.name(r, h, ["rgb", "hdr", "all"])
        if r.random() < 0.7
        else (["rgb", "depth"] if not h else ["rgb", 3])
    ),
    "path": lambda r, h: V.path(r, h, (".obj", ".ply", ".binary", ".png", ".jpg", ".xyz", "")),
    "orient": _names(lambda: ["outward", "keep"]),
    "decades": _f(1.0, 6.0),
    # a caller's output array: usually none; else one of the wrong shape, dtype or layout
    "out": lambda r, h: (
        None
        if not h
        else r.choice([np.zeros(3, np.float64), np.zeros((2, 3), np.float32)[:, ::2], V.hostile_other(r)])
    ),
    # flags
    **{k: V.bools for k in ("cosine", "store", "use_normals", "shadows", "cull_back_faces", "fixed_flag")},
    "ao": lambda r, h: (
        r.choice([None, True, False, {"tau": 2.0, "samples": 8}])
        if not h
        else r.choice([{"tau": -1}, {"samples": 10**9}, {"nope": 1}, V.hostile_other(r)])
    ),
    "progress": lambda r, h: r.choice([None, False]) if not h else r.choice([True, 3, V.hostile_other(r)]),
    "stream": lambda r, h: None,
    "frame": lambda r, h: None if not h else V.hostile_other(r),
    # objects
    "model": _model_like,
    "models": _model_like,
    "mesh": _mesh,
    "obj": _mesh,
    "material": lambda r, h: (
        r.choice([None, "lambert", brdfpy.model("phong")]) if not h else V.name(r, True, [])
    ),
    "camera": _camera,
    "geometry": lambda r, h: None if not h else V.hostile_other(r),
    "f": _callable_f,
    "lobes": _lobes,
    "sample": _sampler,
    "pdf": _pdf,
    "start": _mapping,
    "fixed": _opt(_mapping),
    "ambient_light": _channels(0.0, 1.0),
    # textures (brdfpy.Texture) and texture coordinates
    "uvs": _opt(lambda r, h: _uv(r, h)),
    "tangents": lambda r, h: None if not h else V.hostile_other(r),
    "uv": lambda r, h: _uv(r, h),
    "duv_dx": _opt(lambda r, h: _uv(r, h, 0.01)),
    "duv_dy": _opt(lambda r, h: _uv(r, h, 0.01)),
    "data_or_path": lambda r, h: (
        np.random.default_rng(r.randrange(2**32)).random(r.choice([(4, 4), (3, 5, 3)]), dtype=np.float32)
        if not h
        else r.choice(
            [np.zeros((0, 4, 3)), np.full((2, 2), np.nan), V.path(r, h, (".png", "")), V.hostile_other(r)]
        )
    ),
    "wrap": _names(lambda: ["repeat", "clamp", "mirror"]),
    "filter": _names(lambda: ["nearest", "bilinear", "trilinear"]),
    "colorspace": _opt(_names(lambda: ["srgb", "linear"])),
    "texture": lambda r, h: INSTANCES["Texture"](r) if not h else V.hostile_other(r),
    # texture sources (glTF's derived parameters) and alpha masks
    "kind": _names(lambda: ["texture", "squared", "metallic_diffuse", "metallic_f0"]),
    "reads": lambda r, h: (
        [(INSTANCES["Texture"](r), None, (1.0, 1.0, 1.0))]
        if not h
        else r.choice(
            [[], [(None, 7, 1.0)], [("t", None, (1, 1, 1))], [(None, None, -1.0)], V.hostile_other(r)]
        )
    ),
    "factor": _channels(0.0, 2.0),
    "base_color": lambda r, h: (
        r.choice([_texture(r, 3), (0.9, 0.6, 0.3)]) if not h else r.choice([(-1, 0, 0), V.hostile_other(r)])
    ),
    "metallic": lambda r, h: r.choice([_texture(r, 3).channel(2), 0.5]) if not h else V.hostile_other(r),
    "alpha_mask": _opt(lambda r, h: _texture(r, 4).channel(3) if not h else V.hostile_other(r)),
    "alpha_cutoff": _f(0.0, 1.0),
    "index": _i(0, 3),
    "normal_map": lambda r, h: None if not h else V.hostile_other(r),
    "occlusion_map": lambda r, h: None if not h else V.hostile_other(r),
    "normal_scale": _f(0.0, 2.0),
    "occlusion_strength": _f(0.0, 1.0),
    # measured: RGL .bsdf files and scattered samples
    "inner": lambda r, h: _rgl()._inner if not h else V.hostile_other(r),
    "n_theta_i": _i(1, 4),
    "n_phi_i": _i(1, 4),
    "grid": lambda r, h: (
        (r.randint(2, 6), r.randint(2, 6)) if not h else r.choice([(0, 4), (1, 10**9), V.hostile_other(r)])
    ),
    "angles": _names(lambda: ["degrees", "radians"]),
    "mirror": lambda r, h: V.bools(r, h),
    "min_weight": _f(0.0, 1.0),
    "background": _channels(0.0, 1.0),
    # environment lighting
    "image": _env_image,
    "rotation": _f(-360.0, 360.0),
    "zenith": _channels(0.0, 2.0),
    "horizon": _channels(0.0, 2.0),
    "ground": _channels(0.0, 2.0),
    "top": _f(0.0, 2.0),
    "floor": _f(0.0, 2.0),
    "environment": _environment,
    "env_mode": _names(lambda: ["fast", "monte_carlo"]),
    "env_samples": _i(1, 16),
    "env_seed": _i(0, 2**32),
    "area_samples": _i(1, 4),
    "area_seed": _i(0, 2**32),
    "edge0": _vec,
    "edge1": _vec,
    "two_sided": V.bools,
}

#: Where a parameter name means something else in one place.
OVERRIDES: dict[tuple[str, str], V.Generator] = {
    ("brdfpy.sh.index", "l"): _i(0, 6),
    ("brdfpy.sh.clamped_cosine_zonal", "l"): _i(0, 6),
    ("brdfpy.views.polar", "n"): _i(2, 64),
    ("brdfpy.views.lit_sphere", "light"): _opt(_vec),
    ("brdfpy.views.lit_sphere", "ambient"): _f(0.0, 1.0),
    ("brdfpy.views.lit_sphere", "size"): _i(2, 16),
    ("brdfpy.views.half_diff_slice", "size"): _size_wh,
    ("brdfpy.views.lobe", "n_phi"): _i(3, 16),
    ("brdfpy.views.lobe", "radius"): lambda r, h: V.name(r, h, ["f", "f_cos"]),
    ("brdfpy.sampling.uniform", "count"): _i(1, 64),
    ("brdfpy.sampling.count_arg", "name"): lambda r, h: "count",
    ("brdfpy.sampling.count_arg", "count"): _i(1, 64),
    ("brdfpy.sampling.seed_arg", "seed"): _i(0, 2**32),
    ("brdfpy.checks.directional_albedo", "n_theta"): _i(1, 8),
    ("brdfpy.checks.directional_albedo", "n_phi"): _i(1, 8),
    ("brdfpy.measured.fit", "values"): lambda r, h: _vec(r, h),
    ("brdfpy.measured.fit", "loss"): _names(lambda: list(brdfpy.measured.LOSSES)),
    ("brdfpy.measured.fit", "strategy"): _names(lambda: list(brdfpy.measured.STRATEGIES)),
    ("brdfpy.measured.fit", "jacobian"): _names(lambda: ["auto", "finite_difference"]),
    ("brdfpy.measured.fit", "weights"): _opt(lambda r, h: _sc(r, h, 0.0, 2.0)),
    ("brdfpy.measured.fit", "choices"): lambda r, h: (
        r.choice([None, {"distribution": ["ggx", "beckmann"]}])
        if not h
        else r.choice(
            [{"distribution": "ggx"}, {"roughness": ["ggx"]}, {"distribution": []}, V.hostile_other(r)]
        )
    ),
    ("brdfpy.measured.fit", "multistart"): _i(0, 4),
    ("brdfpy.measured.fit", "tangent"): _opt(_vec),
    ("brdfpy.measured.AnisotropicTabulated", "values"): _aniso_values,
    ("brdfpy.measured.AnisotropicTabulated.from_bytes", "data"): _mit_bytes,
    ("brdfpy.measured.fit", "max_theta"): _f(10.0, 90.0),
    ("brdfpy.measured.compare", "sphere_size"): _i(8, 32),
    ("brdfpy.transforms.translate", "x"): lambda r, h: _f(-2, 2)(r, h) if r.random() < 0.5 else _vec(r, h),
    ("brdfpy.transforms.scale", "sx"): lambda r, h: _f(0.5, 2)(r, h) if r.random() < 0.5 else _vec(r, h),
}


def generator(target: Target, param: inspect.Parameter) -> V.Generator | None:
    g = OVERRIDES.get((target.qualname, param.name))
    if g is None and target.qualname.startswith("brdfpy.views.") and param.name == "n":
        g = _i(2, 64)
    if g is None and param.kind == inspect.Parameter.VAR_KEYWORD:
        return lambda r, h: {}
    if g is None and param.kind == inspect.Parameter.VAR_POSITIONAL:
        return lambda r, h: ()
    if g is None and target.qualname.endswith("="):
        return _setter_value(target)
    return g if g is not None else PARAMS.get(param.name)


def _setter_value(target: Target) -> V.Generator:
    prop = target.qualname.rstrip("=").rsplit(".", 1)[1]
    if prop in ("ambient_light", "background"):
        return _channels(0.0, 1.0)
    return lambda r, h: V.scalars(r, h, 0.0, 1.0)


def missing_generators() -> list[str]:
    """``qualname(param)`` for every parameter no generator covers."""
    return [
        f"{t.qualname}({p.name})"
        for t in targets()
        for p in t.params
        if not p.name.startswith("_") and generator(t, p) is None
    ]


def _model_params(r: random.Random, hostile: bool, args: list[Any]) -> dict[str, Any]:
    """Parameters of ``brdfpy.model(name, **params)``: some of the model's own, plausible or hostile, and
    now and then one it does not have."""
    name = args[0] if args and isinstance(args[0], str) and args[0] in brdfpy.models() else None
    if name is None:
        return {}
    infos = brdfpy.model_info(name)["params"]
    out: dict[str, Any] = {}
    for info in r.sample(infos, min(len(infos), r.randint(0, 3))):
        if hostile:
            out[info["name"]] = r.choice([*V.HOSTILE_FLOATS, "x", None, (1.0, 2.0), [math.nan] * 3])
        else:
            out[info["name"]] = info["default"]
    if hostile and r.random() < 0.3:
        out[r.choice(["alpha", "n", "rho", "colour", "diffuse_color"])] = 0.5
    return out


#: Generators of ``**kwargs`` where they are part of the API.
KWARGS: dict[str, Callable[[random.Random, bool, list[Any]], dict[str, Any]]] = {
    "brdfpy.model": _model_params,
}


# ----------------------------------------------------------------------------------------- outcomes


@dataclass
class Outcome:
    """What one call did: ``kind`` is ``ok``, ``clean`` or ``failure``; ``detail`` says why."""

    target: str
    kind: str
    detail: str = ""
    call: str = ""
    exception: str = ""
    extras: dict[str, Any] = field(default_factory=dict)


#: Messages of Python or NumPy that name nothing the caller passed.
UNCLEAR = re.compile(
    r"math domain error|negative count|bad operand type|unsupported operand|object of type|"
    r"not subscriptable|has no attribute|cannot convert float|could not convert|division by zero|"
    r"index out of range|list index|tuple index|unhashable|not iterable|NoneType|can't multiply|"
    r"invalid literal|setting an array element|inhomogeneous|not callable|must be real number|"
    r"argument must be|only integer scalar|out of bounds|overflow",
    re.IGNORECASE,
)

#: A message that starts by naming what is wrong: ``eta: ...``, ``lobes[2]: ...``, ``(l, m): ...``,
#: ``<memory>: ...``, ``/tmp/x.obj: ...``, ``Light is the base class...``.
NAMED = re.compile(
    r"^\(?[A-Za-z_<>/.~\-0-9\[\]]+(, [a-z_]+)*\)?(\[[^\]]*\])*(\.[a-z_]+)*:|^[A-Z][A-Za-z]+ is "
    # the core's forms that quote the offending value and what is accepted instead
    r'|^parameter "[a-z_0-9]+":|^unknown model "|^model "[a-z_]+" has no parameter "'
    r"|^[a-z_]+ has no parameter '"
    r"|^argument '[a-z_0-9]+':"
)

CLEAN_TYPES = (TypeError, ValueError, OSError)


def _finite(x: Any, depth: int = 0) -> bool:
    """Whether an input holds only finite numbers (non-numbers count as finite: they are refused)."""
    if depth > 3:
        return True
    if isinstance(x, (bool, int, str, bytes)) or x is None:
        return True
    if isinstance(x, float):
        return math.isfinite(x)
    if isinstance(x, complex):
        return math.isfinite(x.real) and math.isfinite(x.imag)
    if isinstance(x, np.ndarray):
        if x.dtype.kind in "fc":
            with np.errstate(all="ignore"):
                if not bool(np.all(np.isfinite(x))):
                    return False
                # Values beyond float32 become ±inf when brdfpy converts them: not finite input.
                return bool(np.all(np.abs(x) <= np.finfo(np.float32).max)) if x.dtype.itemsize >= 4 else True
        return True
    if isinstance(x, np.generic):
        return _finite(np.asarray(x), depth + 1)
    if isinstance(x, (list, tuple)):
        return all(_finite(i, depth + 1) for i in x)
    if isinstance(x, dict):
        return all(_finite(i, depth + 1) for i in x.values())
    return True


def _bad_outputs(x: Any, allow_inf: bool, depth: int = 0) -> str | None:
    """A description of the first NaN (or ∞) in a result, else None."""
    if depth > 3:
        return None
    if isinstance(x, float) and (math.isnan(x) or (math.isinf(x) and not allow_inf)):
        return f"result {x}"
    if isinstance(x, np.ndarray) and x.dtype.kind == "f" and x.size:
        nan = int(np.count_nonzero(np.isnan(x)))
        inf = 0 if allow_inf else int(np.count_nonzero(np.isinf(x)))
        if nan or inf:
            return f"{nan} NaN and {inf} inf of {x.size} values"
    if isinstance(x, (tuple, list)):
        for i in x[:8]:
            d = _bad_outputs(i, allow_inf, depth + 1)
            if d:
                return d
    if isinstance(x, dict):
        for i in list(x.values())[:16]:
            d = _bad_outputs(i, allow_inf, depth + 1)
            if d:
                return d
    return None


#: Results that may hold +∞ by definition: Smith Λ below the horizon.
INF_ALLOWED = {
    "brdfpy.microfacet.lambda_",
    # the standard error of one sample is unknown: +inf
    "brdfpy.sampling.albedo_by_sampling",
    "brdfpy.checks.albedo_by_sampling",
    # a ray that hits nothing has t = +inf
    "brdfpy.RayCaster.closest_hit",
    # a directional light is at distance +inf
    "brdfpy.DirectionalLight.incident",
    "brdfpy.Light.incident",
}

#: Results that may legitimately be NaN-free but are not arrays of values (skip the output scan).
SKIP_OUTPUT_SCAN = {"brdfpy.checks.check"}


def _short(x: Any) -> str:
    if isinstance(x, np.ndarray):
        flat = x.reshape(-1)[:6]
        order = "F" if x.flags.f_contiguous and not x.flags.c_contiguous else "C"
        return (
            f"array(first {flat.tolist()!r}, dtype={x.dtype}, shape={x.shape}, order={order}, "
            f"strides={x.strides})"
        )
    s = repr(x)
    return s if len(s) < 200 else s[:200] + "..."


def draw(target: Target, r: random.Random, hostile: float) -> tuple[list[Any], dict[str, Any]]:
    """Arguments for one call: each parameter plausible or (with probability ``hostile``) hostile;
    optional ones sometimes left out; now and then an unknown keyword."""
    args: list[Any] = []
    kwargs: dict[str, Any] = {}
    positional = True  # until a parameter is skipped or passed by keyword
    for p in target.params:
        if p.name.startswith("_"):
            continue  # private
        g = generator(target, p)
        if g is None:
            raise KeyError(f"{target.qualname}({p.name}): no generator (add one to fuzzing.api.PARAMS)")
        if p.kind == p.VAR_POSITIONAL:
            continue
        if p.kind == p.VAR_KEYWORD:
            extra = KWARGS.get(target.qualname)
            if extra is not None:
                kwargs.update(extra(r, r.random() < hostile, args))
            continue
        if p.default is not p.empty and r.random() < 0.35:
            positional = positional and p.kind == p.POSITIONAL_ONLY
            continue  # use the default
        val = g(r, r.random() < hostile)
        by_position = p.kind == p.POSITIONAL_OR_KEYWORD and positional and r.random() < 0.7
        if p.kind == p.POSITIONAL_ONLY or by_position:
            args.append(val)
        else:
            positional = False
            kwargs[p.name] = val
    if r.random() < 0.03:
        kwargs[r.choice(["bogus", "n_samples_", "colour", "Alpha"])] = 1.0
    if args and r.random() < 0.02:
        args.pop()
    return args, kwargs


def call(target: Target, r: random.Random, hostile: float = 0.35) -> Outcome:
    """Draw arguments for ``target`` from ``r``, call it, classify what happened."""
    try:
        # Building hostile inputs (float64 values past float32, huge integers) may make NumPy warn inside
        # the fixtures; those warnings are the harness's, not the call's, and must not depend on which
        # cached fixtures earlier tests left behind (the same example warned or not with the test order).
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fn = target.get(r)
            args, kwargs = draw(target, r, hostile)
    except Exception as e:  # the fixtures themselves must work
        return Outcome(target.qualname, "failure", f"could not set up the call: {type(e).__name__}: {e}")
    shown = ", ".join([_short(a) for a in args] + [f"{k}={_short(v)}" for k, v in kwargs.items()])
    text = f"{target.qualname}({shown})"
    finite_in = all(_finite(a) for a in args) and all(_finite(v) for v in kwargs.values())
    try:
        with np.errstate(all="ignore"):
            result = fn(*args, **kwargs)
    except CLEAN_TYPES as e:
        msg = str(e)
        if isinstance(e, OSError) and e.filename is not None:
            return Outcome(target.qualname, "clean", msg, text, type(e).__name__)
        if not msg.strip():
            return Outcome(
                target.qualname,
                "failure",
                f"{type(e).__name__} with an empty message",
                text,
                type(e).__name__,
            )
        if UNCLEAR.search(msg) and not NAMED.match(msg):
            return Outcome(
                target.qualname,
                "failure",
                f"unclear message: {type(e).__name__}: {msg}",
                text,
                type(e).__name__,
            )
        names = {p.name for p in target.params} | {"value"}
        python_binding = re.search(
            r"(positional argument|keyword argument|takes \d+|missing \d+ required|got multiple values)", msg
        )
        if NAMED.match(msg) or python_binding or any(re.search(rf"\b{re.escape(n)}\b", msg) for n in names):
            return Outcome(target.qualname, "clean", msg, text, type(e).__name__)
        return Outcome(
            target.qualname,
            "failure",
            f"message names no argument: {type(e).__name__}: {msg}",
            text,
            type(e).__name__,
        )
    except BaseException as e:
        if isinstance(e, (KeyboardInterrupt, SystemExit)):
            raise
        return Outcome(target.qualname, "failure", f"{type(e).__name__}: {e}"[:500], text, type(e).__name__)
    if finite_in and target.qualname not in SKIP_OUTPUT_SCAN:
        bad = _bad_outputs(result, allow_inf=target.qualname in INF_ALLOWED)
        if bad:
            return Outcome(target.qualname, "failure", f"non-finite output from finite input: {bad}", text)
    return Outcome(target.qualname, "ok", "", text)
