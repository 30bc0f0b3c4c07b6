"""Measured BRDFs (Matusik, Pfister, Brand & McMillan 2003, "A Data-Driven Reflectance Model").

A tabulated isotropic BRDF with interpolated look-up, the MERL ``.binary`` format, and fitting an analytic
model's parameters to samples.

The table lives on Rusinkiewicz's half/difference angles ``(θ_h, θ_d, φ_d)`` in the layout of the MERL
database (Matusik et al. 2003): ``θ_h`` nodes at ``(i / n)² · π/2``, ``θ_d`` at ``j / n · π/2``, ``φ_d`` at
``k / n · π`` over ``[0, π)`` (reciprocity makes the BRDF π-periodic in ``φ_d``). Look-ups interpolate
trilinearly. Values are ``f_r`` in 1/sr, linear RGB.

>>> import brdfpy
>>> from brdfpy import measured
>>> m = brdfpy.model("cook_torrance", roughness=0.3)
>>> t = measured.Tabulated.from_model(m, (32, 32, 64))
>>> t.shape
(32, 32, 64)
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any, TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import as_int, as_vectors
from brdfpy._paths import as_path
from brdfpy.models import Model, ParamValue, model

__all__ = ["MERL_RESOLUTION", "FitResult", "Tabulated", "fit"]

#: ``(n_theta_h, n_theta_d, n_phi_d)`` of the files of the MERL BRDF database.
MERL_RESOLUTION = (90, 90, 180)


class Tabulated:
    """An isotropic BRDF tabulated on the MERL half/difference grid, looked up by trilinear interpolation.

    Parameters
    ----------
    table : array_like, shape (n_theta_h, n_theta_d, n_phi_d, 3)
        ``f_r`` [1/sr] at the grid nodes (see the module docs), finite and ``>= 0``; every axis at least 2.
    """

    __slots__ = ("_inner",)

    def __init__(self, table: ArrayLike) -> None:
        a = np.asarray(table)
        if a.dtype.kind not in "fiu":
            raise TypeError(f"table: expected real numbers, got dtype {a.dtype}")
        with np.errstate(over="ignore", invalid="ignore"):
            a32 = np.require(a, np.float32, ["C", "A"])  # contiguous and aligned (e.g. a network buffer)
        self._inner = _brdfpy.Tabulated(a32)

    @classmethod
    def _wrap(cls, inner: _brdfpy.Tabulated) -> Tabulated:
        t = cls.__new__(cls)
        t._inner = inner
        return t

    @classmethod
    def from_model(cls, model: Model, resolution: tuple[int, int, int] = MERL_RESOLUTION) -> Tabulated:
        """Tabulate an isotropic registry model at the nodes of a ``resolution`` grid.

        Nodes with the light or the viewer below the surface hold 0. The interpolation error against the
        model falls as the square of the grid spacing (measured in the Rust tests).
        """
        if not isinstance(model, _brdfpy.Model):
            raise TypeError(f"model: expected a brdfpy.Model, got {type(model).__name__}")
        if not isinstance(resolution, (tuple, list, np.ndarray)):
            raise TypeError(f"resolution: expected 3 integers, got {type(resolution).__name__}")
        if len(resolution) != 3:
            raise ValueError(f"resolution: expected 3 integers (θh, θd, φd), got {len(resolution)}")
        r3 = (
            as_int("resolution[0]", resolution[0], 0, 2**32),
            as_int("resolution[1]", resolution[1], 0, 2**32),
            as_int("resolution[2]", resolution[2], 0, 2**32),
        )
        return cls._wrap(_brdfpy.Tabulated.from_model(model, r3))

    def as_model(self) -> Model:
        """This table as a :class:`brdfpy.Model` named ``"measured"`` (no parameters, physical, isotropic):
        a material for :meth:`brdfpy.Scene.add` (look-up with interpolation during rendering, as in
        Matusik et al. 2003), and a model for :mod:`brdfpy.checks` and batch evaluation. The
        model shares the table (it is immutable), so this costs no copy."""
        return Model("measured", _table=self._inner)

    @classmethod
    def load_merl(cls, path: str | os.PathLike[str]) -> Tabulated:
        """Read a MERL ``.binary`` file (3 little-endian int32 dimensions, then float64 values per channel,
        scaled by 1/1500, 1.15/1500, 1.66/1500). Negative values (MERL's "no data") become 0."""
        with open(as_path("path", path), "rb") as f:
            data = f.read()
        return cls._wrap(_brdfpy.Tabulated.from_merl_bytes(data))

    @classmethod
    def from_merl_bytes(cls, data: bytes) -> Tabulated:
        """Parse the bytes of a MERL ``.binary`` file (see :meth:`load_merl`)."""
        if not isinstance(data, (bytes, bytearray, memoryview)):
            # bytes(-1) would say "negative count", bytes(10**12) would try to allocate a terabyte.
            raise TypeError(f"data: expected the bytes of a MERL file, got {type(data).__name__}")
        return cls._wrap(_brdfpy.Tabulated.from_merl_bytes(bytes(data)))

    def to_merl_bytes(self) -> bytes:
        """The table in the MERL ``.binary`` layout."""
        return self._inner.to_merl_bytes()

    def save_merl(self, path: str | os.PathLike[str]) -> None:
        """Write the table as a MERL ``.binary`` file."""
        with open(as_path("path", path), "wb") as f:
            f.write(self._inner.to_merl_bytes())

    @property
    def shape(self) -> tuple[int, int, int]:
        """``(n_theta_h, n_theta_d, n_phi_d)``."""
        return self._inner.shape

    @property
    def table(self) -> NDArray[np.float32]:
        """A float32 copy of the values, shape ``(n_theta_h, n_theta_d, n_phi_d, 3)``."""
        return self._inner.table

    def eval(self, l: ArrayLike, v: ArrayLike, n: ArrayLike) -> NDArray[np.float32]:
        """``f_r(l, v)`` [1/sr] per RGB channel by trilinear interpolation; 0 unless ``n·l > 0`` and
        ``n·v > 0``.

        Arguments, shapes, broadcasting and errors as for :meth:`brdfpy.Model.eval` (no tangent: the table is
        isotropic): ``(..., 3)`` inputs whose leading dimensions broadcast, float32 output of the broadcast
        shape followed by 3.
        """
        return self._inner._eval(as_vectors("l", l), as_vectors("v", v), as_vectors("n", n))

    def __reduce__(self) -> tuple[Any, ...]:
        # By its float32 values (the constructor keeps them bit for bit).
        return (Tabulated, (self.table,))

    def __repr__(self) -> str:
        return repr(self._inner)


class FitResult(TypedDict):
    """What :func:`fit` returns."""

    model: Model
    values: dict[str, Any]
    rms_log_error: float
    epsilon: float
    iterations: int
    converged: bool
    samples_used: int


def fit(
    model_name: str,
    l: ArrayLike,
    v: ArrayLike,
    n: ArrayLike,
    values: ArrayLike,
    *,
    start: Mapping[str, ParamValue],
    fixed: Mapping[str, ParamValue] | None = None,
    max_iterations: int = 200,
) -> FitResult:
    """Fit the parameters named in ``start`` of registry model ``model_name`` to measured samples.

    Levenberg–Marquardt on the log residuals ``ln(f_model + ε) − ln(f_data + ε)`` with
    ``ε = 0.01 · mean(values)`` (so the specular peak does not dominate), numerical Jacobian, every value kept
    inside the registry's range for it.

    Parameters
    ----------
    model_name : str
        A registry name (see :func:`brdfpy.models`).
    l, v, n : array_like, shape (..., 3)
        Sample directions (broadcast as in :meth:`brdfpy.Model.eval`).
    values : array_like, shape (..., 3)
        Measured ``f_r`` [1/sr], finite and ``>= 0``. Samples with ``l`` or ``v`` below the surface are
        dropped.
    start : mapping
        The free parameters and their starting values (scalar or color parameters; a color is fitted per
        channel).
    fixed : mapping, optional
        Parameters held at the given values (choices such as ``distribution`` go here); the rest keep their
        defaults.
    max_iterations : int
        Most iterations.

    Returns
    -------
    dict
        ``model`` (the fitted :class:`brdfpy.Model`), ``values`` (the free parameters: float, or a 3-tuple for
        a color), ``rms_log_error``, ``epsilon``, ``iterations``, ``converged``, ``samples_used``.
    """
    if not isinstance(model_name, str):
        raise TypeError(f"model_name: expected a str, got {type(model_name).__name__}")
    if not isinstance(max_iterations, int) or max_iterations < 1:
        raise ValueError(f"max_iterations: expected a positive integer, got {max_iterations!r}")
    la, va, na = as_vectors("l", l), as_vectors("v", v), as_vectors("n", n)
    fa = as_vectors("values", values)
    for name, m in (("start", start), ("fixed", fixed)):
        if m is not None and not isinstance(m, Mapping):
            raise TypeError(
                f"{name}: expected a mapping of parameter names to values, got {type(m).__name__}"
            )
    start_d = _plain(dict(start))
    fixed_d = _plain(dict(fixed or {}))
    res = _brdfpy.fit_model(model_name, la, va, na, fa, start_d, fixed_d, max_iterations)
    fitted: dict[str, Any] = dict(res["values"])
    return FitResult(
        model=model(model_name, **fixed_d, **fitted),
        values=fitted,
        rms_log_error=float(res["rms_log_error"]),
        epsilon=float(res["epsilon"]),
        iterations=int(res["iterations"]),
        converged=bool(res["converged"]),
        samples_used=int(res["samples_used"]),
    )


def _plain(d: dict[str, Any]) -> dict[str, Any]:
    # NumPy scalars and arrays → Python numbers and lists, which the compiled module extracts.
    return {k: (x.tolist() if isinstance(x, (np.ndarray, np.generic)) else x) for k, x in d.items()}
