"""The model registry and :class:`Model`, a reflectance model with fixed parameters."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, TypedDict, Union, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import as_vectors

__all__ = ["Model", "ModelInfo", "ParamInfo", "ParamValue", "TexturedModel", "model", "model_info", "models"]

#: What a parameter accepts: a number, a bool, a choice name, or numbers (an RGB color, rows of an array).
ParamValue = Union[float, bool, str, Sequence[float], Sequence[Sequence[float]], NDArray[Any]]


class ParamInfo(TypedDict):
    """One parameter of a model, as the registry documents it."""

    name: str
    kind: str  # "scalar" | "color" | "choice" | "bool" | "array"
    default: Any
    min: float | None
    max: float | None
    unit: str
    doc: str
    choices: tuple[str, ...] | None


class ModelInfo(TypedDict):
    """A registered model: what it computes, where the formula comes from, and its parameters."""

    name: str
    summary: str
    source: str
    physical: bool
    anisotropic: bool
    params: list[ParamInfo]


def models() -> list[str]:
    """Names of every registered reflectance model, in registry order.

    Examples
    --------
    >>> "lambert" in brdfpy.models()
    True
    """
    return list(_brdfpy.model_names())


def model_info(name: str) -> ModelInfo:
    """Everything the registry knows about model ``name``.

    Returns
    -------
    dict
        ``name``, ``summary`` (with the formula), ``source`` (the published paper or book), ``physical`` (a
        BRDF in 1/sr that is reciprocal and energy-conserving, as opposed to a textbook formula offered as
        written), ``anisotropic`` (reads the tangent) and ``params``: a list of dicts with ``name``, ``kind``
        (``"scalar"``, ``"color"``, ``"choice"``, ``"bool"`` or ``"array"``), ``default``, ``min``, ``max``,
        ``unit``, ``doc`` and ``choices`` (the allowed names of a choice, else ``None``).

    Raises
    ------
    ValueError
        If no model has that name (the message lists the known names).
    """
    if not isinstance(name, str):
        raise TypeError(f"name: expected a model name (str), got {type(name).__name__}")
    info: ModelInfo = _brdfpy.model_spec(name)  # type: ignore[assignment]
    return info


class Model(_brdfpy.Model):
    """A reflectance model with fixed, validated parameters; build it with :func:`brdfpy.model`.

    Conventions: every direction points away from the surface (``l`` toward the light, ``v`` toward the
    viewer, ``n`` the surface normal); directions need not be unit length (they are normalised), and a
    zero-length direction gives 0. Colors are linear RGB.

    Attributes
    ----------
    name : str
        Registry name.
    params : dict
        Every parameter's value, defaults filled in.
    physical : bool
        ``True`` for BRDFs in 1/sr; ``False`` for the classic shading formulas (Lambert, Phong, Blinn-Phong as
        in textbooks, toon, Strauss), which are not BRDFs.
    anisotropic : bool
        ``True`` when the model reads ``tangent``.
    """

    __slots__ = ()

    def __new__(cls, name: str, /, **params: Any) -> Model:
        if not isinstance(name, str):
            raise TypeError(f"name: expected a model name (str), got {type(name).__name__}")
        return super().__new__(cls, name, **params)  # type: ignore[return-value]  # an instance of cls

    def __init__(self, name: str, /, **params: Any) -> None:
        # Built by __new__ (the compiled base); defined so that object.__init__ is not handed the arguments.
        pass

    def eval(
        self,
        l: ArrayLike,
        v: ArrayLike,
        n: ArrayLike,
        tangent: ArrayLike | None = None,
        *,
        out: NDArray[np.float32] | None = None,
    ) -> NDArray[np.float32]:
        """The BRDF value ``f_r(l, v)`` per RGB channel [1/sr], without the cosine.

        Physical models give 0 unless both ``n·l > 0`` and ``n·v > 0``. A classic (course) model's
        ``f_r`` is its course formula divided by ``n·l`` (0 where ``n·l <= 0``).

        Parameters
        ----------
        l, v, n : array_like, shape (..., 3)
            Directions toward the light and the viewer, and the surface normal. Float32 or float64, any
            memory layout (float32 C-contiguous input is used without a copy). The leading dimensions
            broadcast NumPy-style: a ``(90, 360, 3)`` grid of ``l`` with one ``(3,)`` ``v`` and ``n``
            gives ``(90, 360, 3)``.
        tangent : array_like, shape (..., 3), optional
            First tangent direction for anisotropic models (projected onto the surface). Without it an
            arbitrary frame is used around ``n``.
        out : numpy.ndarray of float32, optional
            Where to write the result instead of a new array (e.g. one buffer reused across calls, or a
            slice of a larger C-contiguous array): float32, C-contiguous, writeable, of exactly the shape
            of the result, and not sharing memory with an input. Every element is written; ``out`` is
            returned.

        Returns
        -------
        numpy.ndarray of float32, shape (broadcast shape of the inputs' leading dimensions) + (3,)
            ``(3,)`` when every input is a single ``(3,)`` vector (``out`` itself when given).

        Raises
        ------
        ValueError
            A last axis that is not 3, shapes that do not broadcast, empty input, ragged or non-finite
            input (the message names the argument, and the index of a non-finite value); an ``out`` of
            the wrong shape, not C-contiguous, read-only or overlapping an input.
        TypeError
            Non-numeric input (strings, objects, complex or bool arrays); an ``out`` that is not a
            float32 NumPy array.
        """
        # Conversion (brdfpy._arrays.as_vectors) happens in the compiled module, and only when an input is
        # not float32 C-contiguous already: no Python-level work on the common path (small calls).
        return self._eval(l, v, n, tangent, False, out)

    def shade(
        self,
        l: ArrayLike,
        v: ArrayLike,
        n: ArrayLike,
        tangent: ArrayLike | None = None,
        *,
        out: NDArray[np.float32] | None = None,
    ) -> NDArray[np.float32]:
        """What a renderer multiplies by the light's color: the reflected radiance per unit irradiance.

        ``f_r(l, v) · max(n·l, 0)`` [1/sr] for physical models; the course formula exactly as written for
        classic models (e.g. ``kd·max(n·l, 0) + ks·max(n·h, 0)^s`` for ``blinn_phong_classic``).
        Arguments (``out`` too), shapes and errors as for :meth:`eval`.
        """
        return self._eval(l, v, n, tangent, True, out)

    def sample(
        self,
        v: ArrayLike,
        n: ArrayLike,
        u: ArrayLike | None = None,
        *,
        seed: int = 0,
        tangent: ArrayLike | None = None,
        count: int | None = None,
    ) -> tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32]]:
        """Importance-sample light directions for views ``v``: ``(l, weight, pdf)``.

        ``l`` is drawn with density ``pdf`` [1/sr] over solid angle, roughly in proportion to
        ``f_r(l, v) cos θ_l`` (each model's technique is listed in the README, "Sampling"), and
        ``weight = shade(l, v, n) / pdf`` — ``f_r cos θ_l / pdf`` for physical models — exactly as
        :meth:`shade` and :meth:`pdf` compute them from the returned ``l``. The mean of ``weight · L(l)``
        estimates the reflected radiance ``∫ f_r cos θ_l L(l) dω_l``.

        Parameters
        ----------
        v, n : array_like, shape (..., 3)
            View directions and normals (need not be unit length); the leading shapes broadcast as for
            :meth:`eval`.
        u : array_like, shape (..., 3), optional
            Uniform numbers in ``[0, 1)``: ``u[..., 0]`` picks the lobe of a sum, ``u[..., 1:]`` the
            direction. Without it, output element ``i`` (in C order) uses
            :func:`brdfpy.sampling.uniform` ``(·, seed)[i]``, so results depend only on ``seed`` and the
            element, never on the thread count.
        seed : int
            Seed of the numbers used when ``u`` is not given (an integer in ``[0, 2**64)``).
        tangent : array_like, shape (..., 3), optional
            First tangent for anisotropic models, as for :meth:`eval`.
        count : int, optional
            Broadcast the inputs against shape ``(count,)``: e.g. ``count`` samples of one view.

        Returns
        -------
        l : numpy.ndarray of float32, shape S + (3,)
            Unit directions toward the light (world space); ``S`` is the broadcast leading shape.
        weight : numpy.ndarray of float32, shape S + (3,)
            ``shade/pdf`` per RGB channel.
        pdf : numpy.ndarray of float32, shape S
            Solid-angle density of ``l``.

        A sample can fail: where ``v`` is not above the surface (``n·v <= 0``) ``l`` is 0, and where the
        drawn direction is not above it (a glossy lobe near grazing) ``l`` is that direction; both have
        ``pdf = 0`` and ``weight = 0`` (never NaN). Count them with weight 0 in an estimate.

        Raises
        ------
        ValueError
            Shapes that do not broadcast, non-finite directions, ``u`` outside ``[0, 1)`` (the message names
            the argument and the index), a bad ``seed`` or ``count``.

        Examples
        --------
        >>> m = brdfpy.model("lambert", kd=0.5)
        >>> l, w, p = m.sample([0, 0, 1], [0, 0, 1], seed=1, count=4)
        >>> w[:, 0]  # Lambert is sampled exactly: f cos / pdf = kd
        array([0.5, 0.5, 0.5, 0.5], dtype=float32)
        """
        from brdfpy.sampling import count_arg, seed_arg

        t = None if tangent is None else as_vectors("tangent", tangent)
        uu = None if u is None else as_vectors("u", u)
        k = None if count is None else count_arg("count", count)
        return _brdfpy.model_sample(self, as_vectors("v", v), as_vectors("n", n), uu, seed_arg(seed), t, k)

    def pdf(
        self, l: ArrayLike, v: ArrayLike, n: ArrayLike, tangent: ArrayLike | None = None
    ) -> NDArray[np.float32]:
        """The solid-angle density [1/sr] with which :meth:`sample` draws ``l`` for view ``v``.

        0 where ``l`` or ``v`` is not above the surface (``n·l <= 0`` or ``n·v <= 0``) or degenerate.
        Arguments and errors as for :meth:`eval`.

        Returns
        -------
        numpy.ndarray of float32, the broadcast leading shape of the inputs
        """
        t = None if tangent is None else as_vectors("tangent", tangent)
        return _brdfpy.model_pdf(self, as_vectors("l", l), as_vectors("v", v), as_vectors("n", n), t)

    def __reduce__(self) -> tuple[Any, ...]:
        # Pickle by name and resolved parameters (e.g. for multiprocessing); a measured model by its table.
        table = self._measured_table()
        if table is not None:
            return (_rebuild_measured, (table,))
        # The other data-driven models by the bytes of their file (the writers round-trip bit for bit).
        source = self._data_source()
        if source is not None:
            return (_rebuild_from_data, source)
        return (_rebuild, (self.name, self.params))


def _rebuild(name: str, params: dict[str, Any]) -> Model:
    return Model(name, **params)


def _rebuild_measured(table: NDArray[np.float32]) -> Model:
    from brdfpy.measured import Tabulated

    return Tabulated(table).as_model()


def _rebuild_from_data(name: str, data: bytes) -> Model:
    from brdfpy.measured import AnisotropicTabulated, RglBsdf

    if name == "rgl_bsdf":
        return RglBsdf.from_bytes(data).as_model()
    return AnisotropicTabulated.from_bytes(data).as_model()


def model(name: str, /, **params: ParamValue) -> Model:
    """Build the registered model ``name`` with the given parameters; defaults fill the rest.

    Parameters
    ----------
    name : str
        A name from :func:`models`.
    **params
        Parameters documented by :func:`model_info`: numbers, RGB colors (one number for gray or three),
        choice names (case-insensitive), bools, or arrays of rows (e.g. Lafortune ``lobes``).

    Raises
    ------
    ValueError
        Unknown model or parameter name, a value out of its documented range or not finite (e.g. a
        negative roughness), or a choice that does not exist; the message names the parameter.
    TypeError
        A value of the wrong type (e.g. a dict).

    Examples
    --------
    >>> m = brdfpy.model("lambert", kd=(0.8, 0.5, 0.2))
    >>> m.eval([0, 0, 1], [0, 0.6, 0.8], [0, 0, 1])  # kd / pi
    array([0.25464791, 0.15915494, 0.06366198], dtype=float32)

    Any colour or scalar parameter may be a :class:`brdfpy.Texture` instead, read at every shaded point of
    a mesh with texture coordinates: a colour takes the texture's RGB (a 1-channel texture as grey), a
    scalar one channel (``roughness=tex.channel(1)``; a 1-channel texture as it is); a
    :class:`brdfpy.texture.TextureSource` computes a value from textures (a factor, a square, glTF's
    metallic mixes). Values are clamped into the parameter's documented range. The result is a
    :class:`TexturedModel`.
    """
    from brdfpy.texture import Texture, TextureChannel, TextureSource

    bound = {k: v for k, v in params.items() if isinstance(v, (Texture, TextureChannel, TextureSource))}
    if not bound:
        return Model(name, **params)
    info = model_info(name)
    specs = {p["name"]: p for p in info["params"]}
    plain: dict[str, Any] = {k: v for k, v in params.items() if k not in bound}
    for k, t in bound.items():
        spec = specs.get(k)
        if spec is None:
            Model(name, **{k: 0.0})  # the registry's own message (unknown or renamed parameter)
            raise ValueError(f"{name} has no parameter {k!r}")  # pragma: no cover - the line above raises
        if isinstance(t, TextureSource):
            mean = t.mean()
        elif isinstance(t, TextureChannel):
            mean = np.asarray([t.texture.mean[t.index]] * 3)
        else:
            mean = np.asarray(t.mean[:3])
        lo, hi = spec["min"], spec["max"]
        mean = np.clip(mean, -np.inf if lo is None else lo, np.inf if hi is None else hi)
        if spec["kind"] == "color":
            plain[k] = [float(x) for x in mean]
        elif spec["kind"] == "scalar":
            if isinstance(t, Texture) and t.channels != 1:
                raise ValueError(
                    f"{k}: is a scalar parameter: it reads one channel of a {t.channels}-channel texture; "
                    f"choose it with tex.channel(k) (e.g. channel(1), green, for glTF's roughness)"
                )
            plain[k] = float(mean[0])
        else:
            raise ValueError(
                f"{k}: is a {spec['kind']} parameter of {name}: only colour and scalar parameters take a "
                "texture"
            )
    return TexturedModel._build(name, bound, plain)


class TexturedModel(Model):
    """A :class:`Model` some of whose parameters are read from textures (from :func:`brdfpy.model` with a
    :class:`brdfpy.Texture` value). It renders on meshes with texture coordinates (``Mesh(..., uvs=...)``);
    :attr:`params` holds the textures' means (clamped into range) for the bound parameters, the value used
    for the material's default ambient reflectance. :meth:`eval`, :meth:`shade`, :meth:`sample` and
    :meth:`pdf` refuse: a texture needs texture coordinates, which directions alone do not have;
    ``brdfpy.model(m.name, **m.params)`` is the model at the means."""

    __slots__ = ("_textures",)

    _textures: dict[str, Any]

    @classmethod
    def _build(cls, name: str, textures: dict[str, Any], params: dict[str, Any]) -> TexturedModel:
        m = cast(TexturedModel, cls.__new__(cls, name, **params))
        m._textures = dict(textures)
        return m

    @property
    def textures(self) -> dict[str, Any]:
        """The bound parameters: name → :class:`brdfpy.Texture`, ``Texture.channel(k)`` or
        :class:`brdfpy.texture.TextureSource`."""
        return dict(self._textures)

    def _refuse(self, what: str) -> ValueError:
        names = ", ".join(self._textures)
        return ValueError(
            f"{what}: {names} of this {self.name} model are textures, which need texture coordinates: "
            f"render it on a mesh with uvs (Scene.add), or use brdfpy.model({self.name!r}, **m.params), the "
            f"model at the textures' means"
        )

    def eval(self, *args: Any, **kwargs: Any) -> NDArray[np.float32]:
        """Refused (see :class:`TexturedModel`)."""
        raise self._refuse("eval")

    def shade(self, *args: Any, **kwargs: Any) -> NDArray[np.float32]:
        """Refused (see :class:`TexturedModel`)."""
        raise self._refuse("shade")

    def sample(
        self, *args: Any, **kwargs: Any
    ) -> tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32]]:
        """Refused (see :class:`TexturedModel`)."""
        raise self._refuse("sample")

    def pdf(self, *args: Any, **kwargs: Any) -> NDArray[np.float32]:
        """Refused (see :class:`TexturedModel`)."""
        raise self._refuse("pdf")

    def __repr__(self) -> str:
        plain = {k: v for k, v in self.params.items() if k not in self._textures}
        parts = [repr(self.name)] + [f"{k}={v!r}" for k, v in self._textures.items()]
        parts += [f"{k}={v!r}" for k, v in plain.items()]
        return f"brdfpy.model({', '.join(parts)})"

    def __reduce__(self) -> Any:
        return (_rebuild_textured, (self.name, self._textures, dict(self.params)))


def _rebuild_textured(name: str, textures: dict[str, Any], params: dict[str, Any]) -> TexturedModel:
    plain = {k: v for k, v in params.items() if k not in textures}
    return TexturedModel._build(name, textures, {**plain, **{k: params[k] for k in textures}})
