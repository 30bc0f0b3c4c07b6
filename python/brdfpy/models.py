"""The model registry and :class:`Model`, a reflectance model with fixed parameters."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, TypedDict, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import as_vec3_args

__all__ = ["Model", "ModelInfo", "ParamInfo", "ParamValue", "model", "model_info", "models"]

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
        ``name``, ``summary`` (with the formula), ``source`` (seed and/or paper), ``physical`` (a BRDF in
        1/sr that is reciprocal and energy-conserving, as opposed to a course formula offered as written),
        ``anisotropic`` (reads the tangent) and ``params``: a list of dicts with ``name``, ``kind``
        (``"scalar"``, ``"color"``, ``"choice"``, ``"bool"`` or ``"array"``), ``default``, ``min``, ``max``,
        ``unit``, ``doc`` and ``choices`` (the allowed names of a choice, else ``None``).

    Raises
    ------
    ValueError
        If no model has that name (the message lists the known names).
    """
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
        ``True`` for BRDFs in 1/sr; ``False`` for the course formulas of seeds 000 and 004.
    anisotropic : bool
        ``True`` when the model reads ``tangent``.
    """

    __slots__ = ()

    def eval(
        self, l: ArrayLike, v: ArrayLike, n: ArrayLike, tangent: ArrayLike | None = None
    ) -> NDArray[np.float32]:
        """The BRDF value ``f_r(l, v)`` per RGB channel [1/sr], without the cosine.

        Physical models give 0 unless both ``n·l > 0`` and ``n·v > 0``. A classic (course) model's
        ``f_r`` is its course formula divided by ``n·l`` (0 where ``n·l <= 0``).

        Parameters
        ----------
        l, v, n : array_like, shape (N, 3) or (3,)
            Directions toward the light and the viewer, and the surface normal. Float32 or float64, any
            memory layout; a ``(3,)`` or ``(1, 3)`` input is broadcast against the others.
        tangent : array_like, shape (N, 3) or (3,), optional
            First tangent direction for anisotropic models (projected onto the surface). Without it an
            arbitrary frame around ``n`` is used.

        Returns
        -------
        numpy.ndarray of float32, shape (N, 3), or (3,) when every input was (3,)

        Raises
        ------
        ValueError
            Wrong shapes, shapes that do not broadcast, empty, ragged or non-finite input (the message
            names the argument).
        TypeError
            Non-numeric input (strings, objects, complex or bool arrays).
        """
        return self._batch(l, v, n, tangent, shade=False)

    def shade(
        self, l: ArrayLike, v: ArrayLike, n: ArrayLike, tangent: ArrayLike | None = None
    ) -> NDArray[np.float32]:
        """What a renderer multiplies by the light's color: the reflected radiance per unit irradiance.

        ``f_r(l, v) · max(n·l, 0)`` [1/sr] for physical models; the course formula exactly as written for
        classic models (e.g. ``kd·max(n·l, 0) + ks·max(n·h, 0)^s`` for ``blinn_phong_classic``).
        Arguments, shapes and errors as for :meth:`eval`.
        """
        return self._batch(l, v, n, tangent, shade=True)

    def _batch(
        self, l: ArrayLike, v: ArrayLike, n: ArrayLike, tangent: ArrayLike | None, shade: bool
    ) -> NDArray[np.float32]:
        (la, va, na, ta), single = as_vec3_args(("tangent",), l=l, v=v, n=n, tangent=tangent)
        assert la is not None and va is not None and na is not None
        out = self._eval(la, va, na, ta, shade)
        return out.reshape(3) if single else out

    def __reduce__(self) -> tuple[Any, ...]:
        # Pickle by name and resolved parameters (e.g. for multiprocessing); a measured model by its table.
        table = self._measured_table()
        if table is not None:
            return (_rebuild_measured, (table,))
        return (_rebuild, (self.name, self.params))


def _rebuild(name: str, params: dict[str, Any]) -> Model:
    return Model(name, **params)


def _rebuild_measured(table: NDArray[np.float32]) -> Model:
    from brdfpy.measured import Tabulated

    return Tabulated(table).as_model()


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
    >>> m = brdfpy.model("lambert", albedo=(0.8, 0.5, 0.2))
    >>> m.eval([0, 0, 1], [0, 0.6, 0.8], [0, 0, 1])  # albedo / pi
    array([0.25464791, 0.15915494, 0.06366198], dtype=float32)
    """
    return Model(name, **params)
