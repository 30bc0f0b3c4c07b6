"""Measured BRDFs (Matusik, Pfister, Brand & McMillan 2003, "A Data-Driven Reflectance Model").

A tabulated isotropic BRDF with interpolated look-up; an anisotropic 4-D table
(:class:`AnisotropicTabulated`, the MIT CSAIL ``.dat`` data of Ngan, Durand & Matusik 2005); the file formats
of measured materials — MERL ``.binary``, MIT CSAIL ``.dat``, RGL ``.bsdf`` (Dupuy & Jakob 2018, evaluated as
Mitsuba 3 does: :class:`RglBsdf`) and CSV rows of scattered gonioreflectometer measurements
(:meth:`Tabulated.from_samples`, :meth:`Tabulated.from_csv`); and fitting an analytic model's parameters to
samples or tables.

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
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import _as_numeric, as_int, as_vectors
from brdfpy._brdfpy import BrdfError
from brdfpy._paths import as_path
from brdfpy.image import Image
from brdfpy.models import Model, ParamValue
from brdfpy.models import model as _model

if TYPE_CHECKING:  # views imports this module
    from brdfpy.views import Albedo, HalfDiffSlice

__all__ = [
    "LOSSES",
    "MERL_RESOLUTION",
    "MIT_RESOLUTION",
    "STRATEGIES",
    "AnisotropicTabulated",
    "ChannelError",
    "Comparison",
    "Coverage",
    "FitReport",
    "FitResult",
    "RglBsdf",
    "Tabulated",
    "compare",
    "fit",
]

#: ``(n_theta_h, n_theta_d, n_phi_d)`` of the files of the MERL BRDF database.
MERL_RESOLUTION = (90, 90, 180)

#: ``(n_theta_in, n_theta_out, n_phi_diff, n_phi_in)`` the BRDF Explorer's shader assumes for the MIT CSAIL
#: anisotropic files (``measuredAniso.func``): 32.8 M cells, 394 MB of RGB float32.
MIT_RESOLUTION = (45, 45, 180, 90)


def _resolution(name: str, resolution: object) -> tuple[int, int, int]:
    if not isinstance(resolution, (tuple, list, np.ndarray)):
        raise TypeError(f"{name}: expected 3 integers, got {type(resolution).__name__}")
    if len(resolution) != 3:
        raise ValueError(f"{name}: expected 3 integers (θh, θd, φd), got {len(resolution)}")
    return (
        as_int(f"{name}[0]", resolution[0], 0, 2**32),
        as_int(f"{name}[1]", resolution[1], 0, 2**32),
        as_int(f"{name}[2]", resolution[2], 0, 2**32),
    )


def _dims(name: str, dims: object) -> tuple[int, int, int, int]:
    if not isinstance(dims, (tuple, list, np.ndarray)):
        raise TypeError(f"{name}: expected 4 integers, got {type(dims).__name__}")
    if len(dims) != 4:
        raise ValueError(f"{name}: expected 4 integers (θ_in, θ_out, φ_diff, φ_in), got {len(dims)}")
    d = tuple(as_int(f"{name}[{k}]", dims[k], 0, 2**32) for k in range(4))
    return (d[0], d[1], d[2], d[3])


def _scale(scale: object) -> float:
    if isinstance(scale, bool) or not isinstance(scale, (int, float, np.integer, np.floating)):
        raise TypeError(f"scale: expected a number, got {type(scale).__name__}")
    x = float(scale)
    if not (np.isfinite(x) and x > 0.0):
        raise ValueError(f"scale: must be finite and > 0, got {scale!r}")
    return x


def _flag(name: str, x: object) -> bool:
    if not isinstance(x, (bool, np.bool_)):
        raise TypeError(f"{name}: expected a bool, got {type(x).__name__}")
    return bool(x)


def _read(path: str | os.PathLike[str]) -> tuple[str, bytes]:
    p = as_path("path", path)
    with open(p, "rb") as f:
        return p, f.read()


def _bytes(name: str, data: object) -> bytes:
    if not isinstance(data, (bytes, bytearray, memoryview)):
        # bytes(-1) would say "negative count", bytes(10**12) would try to allocate a terabyte.
        raise TypeError(f"{name}: expected bytes, got {type(data).__name__}")
    return bytes(data)


@dataclass(frozen=True)
class Coverage:
    """How :meth:`Tabulated.from_samples` covered its table (``brdf_core::measured::Coverage``)."""

    #: Samples splatted.
    samples: int
    #: Nodes of the table.
    nodes: int
    #: Nodes with the light or the viewer below the surface (they hold 0).
    below_horizon: int
    #: Nodes estimated from samples (kernel weight at least ``min_weight``).
    covered: int
    #: Nodes filled from their neighbours (no sample reached them).
    filled: int
    #: Largest fill distance in grid steps from the nearest covered node (0: nothing filled).
    max_fill_distance: int
    #: ``covered`` as a fraction of the nodes above the horizon.
    fraction: float


class Tabulated:
    """An isotropic BRDF tabulated on the MERL half/difference grid, looked up by trilinear interpolation.

    Parameters
    ----------
    table : array_like, shape (n_theta_h, n_theta_d, n_phi_d, 3)
        ``f_r`` [1/sr] at the grid nodes (see the module docs), finite and ``>= 0``; every axis at least 2.
    """

    __slots__ = ("_coverage", "_inner")

    def __init__(self, table: ArrayLike) -> None:
        a = np.asarray(table)
        if a.dtype.kind not in "fiu":
            raise TypeError(f"table: expected real numbers, got dtype {a.dtype}")
        with np.errstate(over="ignore", invalid="ignore"):
            a32 = np.require(a, np.float32, ["C", "A"])  # contiguous and aligned (e.g. a network buffer)
        self._inner = _brdfpy.Tabulated(a32)
        self._coverage: Coverage | None = None

    @classmethod
    def _wrap(cls, inner: _brdfpy.Tabulated, coverage: Coverage | None = None) -> Tabulated:
        t = cls.__new__(cls)
        t._inner = inner
        t._coverage = coverage
        return t

    @property
    def coverage(self) -> Coverage | None:
        """How the samples covered the table, for a table made by :meth:`from_samples` or :meth:`from_csv`
        (``None`` for any other table, and after pickling)."""
        return self._coverage

    @classmethod
    def from_samples(
        cls,
        l: ArrayLike,
        v: ArrayLike,
        values: ArrayLike,
        n: ArrayLike | None = None,
        *,
        resolution: tuple[int, int, int] = (32, 32, 64),
        mirror: bool = True,
        min_weight: float = 1e-3,
    ) -> Tabulated:
        """A table from scattered measurements: ``values`` (``f_r`` [1/sr], RGB) at light directions ``l`` and
        view directions ``v`` about normals ``n`` (default ``+z``); ``(..., 3)`` arrays that broadcast.

        The interpolation (``brdf_core::measured::samples``): each sample is splatted onto the eight nodes
        around it with the trilinear weights of the look-up (a tent kernel one cell wide, in the table's index
        coordinates), and a node holds ``Σ w f / Σ w`` (Nadaraya–Watson kernel regression). Reciprocity is
        built in (``l`` and ``v`` swapped land in the same cells); with ``mirror`` each sample is also used at
        ``π − φ_d`` (the mirror symmetry of isotropic BRDFs). Nodes below the horizon hold 0; nodes no sample
        reached (``Σ w < min_weight``) take the mean of their known neighbours, ring after ring from the
        covered ones. :attr:`coverage` says how many nodes were covered and filled.

        Raises :class:`brdfpy.BrdfError` naming the argument for directions below the horizon (``n·l <= 0`` or
        ``n·v <= 0``), non-finite or zero vectors, non-finite or negative values.
        """
        r3 = _resolution("resolution", resolution)
        if not isinstance(mirror, (bool, np.bool_)):
            raise TypeError(f"mirror: expected a bool, got {type(mirror).__name__}")
        if isinstance(min_weight, bool) or not isinstance(min_weight, (int, float, np.integer, np.floating)):
            raise TypeError(f"min_weight: expected a number, got {type(min_weight).__name__}")
        mw = float(min_weight)
        nn = as_vectors("n", (0.0, 0.0, 1.0) if n is None else n)
        inner, cov = _brdfpy.Tabulated.from_samples(
            as_vectors("l", l), as_vectors("v", v), nn, as_vectors("values", values), r3, bool(mirror), mw
        )
        return cls._wrap(inner, Coverage(**cov))

    @classmethod
    def from_csv(
        cls,
        path: str | os.PathLike[str],
        *,
        angles: str = "degrees",
        resolution: tuple[int, int, int] = (32, 32, 64),
        mirror: bool = True,
        min_weight: float = 1e-3,
    ) -> Tabulated:
        """A table (:meth:`from_samples`) from a CSV file of gonioreflectometer rows
        ``theta_i, phi_i, theta_o, phi_o, R, G, B``: light (incident) and viewer (outgoing) polar angles from
        the normal and azimuths, in ``angles`` (``"degrees"`` or ``"radians"``), then ``f_r`` [1/sr]. A first
        row of column names, blank lines and ``#`` comments are skipped. Errors name the file, the line and
        the column (e.g. a polar angle of 90° or more: a direction on or below the horizon)."""
        if not isinstance(angles, str):
            raise TypeError(f'angles: expected "degrees" or "radians", got {type(angles).__name__}')
        p, data = _read(path)
        try:
            l, v, f = _brdfpy.read_samples_csv_bytes(data, angles)
        except BrdfError as e:
            if str(e).startswith("angles:"):
                raise
            raise BrdfError(f"{p}: {e}") from None
        return cls.from_samples(l, v, f, resolution=resolution, mirror=mirror, min_weight=min_weight)

    @classmethod
    def from_model(cls, model: Model, resolution: tuple[int, int, int] = MERL_RESOLUTION) -> Tabulated:
        """Tabulate an isotropic registry model at the nodes of a ``resolution`` grid.

        Nodes with the light or the viewer below the surface hold 0. The interpolation error against the
        model falls as the square of the grid spacing (measured in the Rust tests).
        """
        if not isinstance(model, _brdfpy.Model):
            raise TypeError(f"model: expected a brdfpy.Model, got {type(model).__name__}")
        return cls._wrap(_brdfpy.Tabulated.from_model(model, _resolution("resolution", resolution)))

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


class AnisotropicTabulated:
    """An anisotropic BRDF tabulated over ``(θ_in, θ_out, φ_diff, φ_in)`` in the tangent frame, looked up by
    multilinear interpolation: the MIT CSAIL anisotropic data (A. Ngan, F. Durand, W. Matusik, "Experimental
    Analysis of BRDF Models", EGSR 2005) in the ``.dat`` layout the BRDF Explorer reads (B. Burley, Disney
    2012). Details: ``brdf_core::measured::anisotropic`` and ``mit_dat``.

    "in" is the light ``l``, "out" the viewer ``v``; in the frame (tangent ``t``, bitangent ``b = n × t``,
    normal ``n``): ``θ_in``, ``θ_out`` are the polar angles from ``n`` in ``[0, π/2]``;
    ``φ_in = atan2(−l·b, −l·t)`` in ``[0, 2π)``, the azimuth of ``−l`` (the direction the light travels), as
    the BRDF Explorer's shader measures it, so that a file has the same orientation in both programs;
    ``φ_diff = φ_out − φ_in`` (``φ_out`` likewise of ``v``) in ``[0, 2π)``, or ``[0, π)`` for a ``half_data``
    table, whose other half follows from reciprocity. Every axis has uniform bins whose values belong to their
    centres ``(i + ½)·range/n``; between centres the look-up interpolates multilinearly, along ``θ`` it holds
    the first and last values beyond them, along ``φ`` it wraps around. Cells without data (negative in a
    file: a cell is without data when any channel is) hold 0 and are interpolated as 0 (continuous; the BRDF
    Explorer shows such bins black); :attr:`valid` is the mask, :attr:`coverage` its fraction.

    Parameters
    ----------
    values : array_like, shape (n_theta_in, n_theta_out, n_phi_diff, n_phi_in, 3)
        RGB values at the bins, finite and ``>= 0`` where there are data; every axis at least 1 bin.
    valid : array_like of bool, shape (n_theta_in, n_theta_out, n_phi_diff, n_phi_in), optional
        The cells that have data (default: all).
    half_data : bool
        ``φ_diff`` covers ``[0, π)`` rather than ``[0, 2π)``.
    """

    __slots__ = ("_inner",)

    def __init__(self, values: ArrayLike, valid: ArrayLike | None = None, *, half_data: bool = False) -> None:
        a = np.asarray(values)
        if a.dtype.kind not in "fiu":
            raise TypeError(f"values: expected real numbers, got dtype {a.dtype}")
        with np.errstate(over="ignore", invalid="ignore"):
            a32 = np.require(a, np.float32, ["C", "A"])
        m = None
        if valid is not None:
            mv = np.asarray(valid)
            if mv.dtype != np.bool_:
                raise TypeError(f"valid: expected an array of bool, got dtype {mv.dtype}")
            m = np.require(mv, np.bool_, ["C", "A"])
        self._inner = _brdfpy.AnisotropicTabulated(a32, m, _flag("half_data", half_data))

    @classmethod
    def _wrap(cls, inner: _brdfpy.AnisotropicTabulated) -> AnisotropicTabulated:
        t = cls.__new__(cls)
        t._inner = inner
        return t

    @classmethod
    def read_mit(cls, path: str | os.PathLike[str], *, scale: float = 1.0) -> AnisotropicTabulated:
        """Read a MIT CSAIL anisotropic ``.dat`` file: a header of 16 little-endian int32 (the bins of
        ``θ_in, θ_out, φ_diff, φ_in``; ``[6]`` paramType 1, ``[7]`` binType 0, ``[9]`` half_data, ``[10]``
        num_channels 3), then float32 values, all red, then all green, then all blue, ``φ_in`` fastest.
        Every header field is checked and the file must be exactly as long as the header says; errors name the
        file and the field. Values are kept as stored, times ``scale`` (the BRDF Explorer displays 10 times
        the stored values: pass 10 to match it)."""
        p, data = _read(path)
        try:
            return cls._wrap(_brdfpy.AnisotropicTabulated.from_mit_bytes(data, _scale(scale)))
        except BrdfError as e:
            if str(e).startswith("scale"):
                raise
            raise BrdfError(f"{p}: {e}") from None

    @classmethod
    def from_bytes(cls, data: bytes, *, scale: float = 1.0) -> AnisotropicTabulated:
        """Parse the bytes of a MIT CSAIL ``.dat`` file (see :meth:`read_mit`)."""
        return cls._wrap(_brdfpy.AnisotropicTabulated.from_mit_bytes(_bytes("data", data), _scale(scale)))

    def to_bytes(self, *, scale: float = 1.0) -> bytes:
        """The table as a MIT CSAIL ``.dat`` file (values divided by ``scale``, cells without data written as
        −1, reserved header fields 0); :meth:`from_bytes` reads it back bit for bit."""
        return self._inner.to_mit_bytes(_scale(scale))

    def write_mit(self, path: str | os.PathLike[str], *, scale: float = 1.0) -> None:
        """Write the table as a MIT CSAIL ``.dat`` file (see :meth:`to_bytes`)."""
        data = self.to_bytes(scale=scale)
        with open(as_path("path", path), "wb") as f:
            f.write(data)

    @classmethod
    def from_model(
        cls, model: Model, dims: tuple[int, int, int, int], *, half_data: bool = False
    ) -> AnisotropicTabulated:
        """Tabulate a model at the bin centres of ``dims = (n_theta_in, n_theta_out, n_phi_diff, n_phi_in)``,
        with normal ``+z`` and tangent ``+x`` (``half_data``: ``φ_diff`` over ``[0, π)`` only, which assumes a
        reciprocal model). Isotropic and anisotropic models alike; the interpolation error against the model
        falls as the square of the bin width (measured in the tests)."""
        if not isinstance(model, _brdfpy.Model):
            raise TypeError(f"model: expected a brdfpy.Model, got {type(model).__name__}")
        d = _dims("dims", dims)
        return cls._wrap(_brdfpy.AnisotropicTabulated.from_model(model, d, _flag("half_data", half_data)))

    @property
    def dims(self) -> tuple[int, int, int, int]:
        """``(n_theta_in, n_theta_out, n_phi_diff, n_phi_in)``."""
        return self._inner.dims

    @property
    def half_data(self) -> bool:
        """Whether ``φ_diff`` covers ``[0, π)`` (reciprocity gives the rest)."""
        return self._inner.half_data

    @property
    def values(self) -> NDArray[np.float32]:
        """A float32 copy of the values, shape ``dims + (3,)`` (0 in cells without data)."""
        return self._inner.values

    @property
    def valid(self) -> NDArray[np.bool_]:
        """A copy of the mask of the cells that have data, shape ``dims``."""
        return self._inner.valid

    @property
    def coverage(self) -> float:
        """The fraction of the cells that have data."""
        return self._inner.coverage

    def eval(
        self, l: ArrayLike, v: ArrayLike, n: ArrayLike = (0.0, 0.0, 1.0), tangent: ArrayLike | None = None
    ) -> NDArray[np.float32]:
        """The interpolated value at light ``l`` and viewer ``v`` (``(..., 3)`` arrays that broadcast) about
        normal ``n``, in the frame of ``tangent`` (projected onto the surface; without it, the arbitrary frame
        of each normal, whose tangent is ``+x`` for ``n = +z``); 0 unless ``n·l > 0`` and ``n·v > 0``."""
        t = None if tangent is None else as_vectors("tangent", tangent)
        return self._inner._eval(as_vectors("l", l), as_vectors("v", v), as_vectors("n", n), t)

    def as_model(self) -> Model:
        """This table as a :class:`brdfpy.Model` named ``"measured_anisotropic"`` (no parameters, physical,
        anisotropic: pass tangents): a material for :meth:`brdfpy.Scene.add` and a model for batch evaluation
        and :mod:`brdfpy.checks`. The model shares the table."""
        return Model("measured_anisotropic", _table=self._inner)

    def __reduce__(self) -> tuple[Any, ...]:
        # By the bytes of its .dat file (the writer and reader round-trip bit for bit, mask included).
        return (_aniso_from_bytes, (self.to_bytes(),))

    def __repr__(self) -> str:
        return repr(self._inner)


def _aniso_from_bytes(data: bytes) -> AnisotropicTabulated:
    return AnisotropicTabulated.from_bytes(data)


class RglBsdf:
    """A material of the RGL database (``.bsdf``, RGB version; Dupuy & Jakob 2018, "An Adaptive
    Parameterization for Efficient Material Acquisition and Rendering"), evaluated as Mitsuba 3's ``measured``
    plugin evaluates it: the inverse of the visible-normal warp, bilinear interpolation of the values on the
    sample grid, linear interpolation between the measured incident directions, the Jacobian term when the
    file asks for it. :meth:`eval` returns ``f_r`` [1/sr] (Mitsuba's value, ``f_r · cos θ_o``, divided by
    ``n·l``), with ``v`` as Mitsuba's incident direction ``wi``. Isotropic and anisotropic files (the latter
    with their 2- or 4-fold symmetry); spectral files are refused. Details: ``brdf_core::measured::rgl_bsdf``.
    """

    __slots__ = ("_inner",)

    def __init__(self, inner: _brdfpy.RglBsdf) -> None:
        if not isinstance(inner, _brdfpy.RglBsdf):
            raise TypeError(
                "inner: use RglBsdf.load(path), RglBsdf.from_bytes(data) or RglBsdf.from_model(model)"
            )
        self._inner = inner

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> RglBsdf:
        """Read a ``.bsdf`` file; errors name the file and the field (truncated data, wrong magic, shapes that
        do not match, NaN or negative densities)."""
        p, data = _read(path)
        try:
            return cls(_brdfpy.RglBsdf.from_bytes(data))
        except BrdfError as e:
            raise BrdfError(f"{p}: {e}") from None

    @classmethod
    def from_bytes(cls, data: bytes) -> RglBsdf:
        """Parse the bytes of a ``.bsdf`` file (see :meth:`load`)."""
        try:
            return cls(_brdfpy.RglBsdf.from_bytes(_bytes("data", data)))
        except _brdfpy.BrdfError as e:
            # The reader names the element (e.g. "tensor file: wrong magic"); the argument is `data`.
            raise _brdfpy.BrdfError(f"data: {e}") from None

    @classmethod
    def from_model(
        cls, model: Model, *, n_theta_i: int = 16, n_phi_i: int = 16, grid: tuple[int, int] = (64, 64)
    ) -> RglBsdf:
        """A ``.bsdf`` of a registry model with identity warps (uniform VNDF, luminance, NDF and σ, no
        Jacobian): the values ``f_r · cos θ_o`` on a ``grid = (h, w)`` over ``(u_φm, u_θm)`` for ``n_theta_i``
        incident polar angles (``(t/(n−1))² · 88°``) and, for an anisotropic model, ``n_phi_i`` azimuths over
        ``[−π, π]``. Mitsuba reads it; it is not Dupuy & Jakob's adaptive parameterisation (that needs the
        model's VNDF), so it needs a finer grid for the same accuracy."""
        if not isinstance(model, _brdfpy.Model):
            raise TypeError(f"model: expected a brdfpy.Model, got {type(model).__name__}")
        if not isinstance(grid, (tuple, list)) or len(grid) != 2:
            raise TypeError("grid: expected 2 integers (h, w)")
        g = (as_int("grid[0]", grid[0], 0, 2**32), as_int("grid[1]", grid[1], 0, 2**32))
        nt = as_int("n_theta_i", n_theta_i, 0, 2**32)
        npi = as_int("n_phi_i", n_phi_i, 0, 2**32)
        return cls(_brdfpy.RglBsdf.from_model(model, nt, npi, g))

    def to_bytes(self) -> bytes:
        """The ``.bsdf`` file (a Mitsuba tensor file, fields aligned to 8 bytes)."""
        return self._inner.to_bytes()

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write the ``.bsdf`` file."""
        with open(as_path("path", path), "wb") as f:
            f.write(self._inner.to_bytes())

    @property
    def description(self) -> str:
        """The material's name (the file's ``description`` field)."""
        return self._inner.description

    @property
    def isotropic(self) -> bool:
        """Whether the file is isotropic (``phi_i`` has at most two entries)."""
        return self._inner.isotropic

    @property
    def jacobian(self) -> bool:
        """Whether the values are multiplied by ``ndf(u_m) / (4 σ(u_i))``."""
        return self._inner.jacobian

    @property
    def theta_i(self) -> NDArray[np.float32]:
        """The measured incident polar angles [radians]."""
        return self._inner.theta_i

    @property
    def phi_i(self) -> NDArray[np.float32]:
        """The measured incident azimuths [radians]."""
        return self._inner.phi_i

    @property
    def shape(self) -> tuple[int, int, int, int, int]:
        """The shape of the ``rgb`` field, ``(n_phi_i, n_theta_i, 3, h, w)``."""
        return self._inner.rgb_shape

    def eval(
        self, l: ArrayLike, v: ArrayLike, n: ArrayLike = (0.0, 0.0, 1.0), tangent: ArrayLike | None = None
    ) -> NDArray[np.float32]:
        """``f_r(l, v)`` [1/sr] per RGB channel; 0 unless ``n·l > 0`` and ``n·v > 0``. ``(..., 3)`` inputs
        that broadcast; ``tangent`` orients an anisotropic material (default: a tangent chosen from ``n``)."""
        t = None if tangent is None else as_vectors("tangent", tangent)
        return self._inner._eval(as_vectors("l", l), as_vectors("v", v), as_vectors("n", n), t)

    def pdf(
        self, l: ArrayLike, v: ArrayLike, n: ArrayLike = (0.0, 0.0, 1.0), tangent: ArrayLike | None = None
    ) -> NDArray[np.float32]:
        """The density [1/sr] with which Mitsuba's ``measured`` plugin samples ``l`` given ``v``, shape of the
        broadcast inputs."""
        t = None if tangent is None else as_vectors("tangent", tangent)
        out = self._inner._eval(as_vectors("l", l), as_vectors("v", v), as_vectors("n", n), t, "pdf")
        return np.ascontiguousarray(out[..., 0])

    def as_model(self) -> Model:
        """This material as a :class:`brdfpy.Model` named ``"rgl_bsdf"`` (no parameters, physical; an
        anisotropic file is oriented by the tangent): a material for :meth:`brdfpy.Scene.add` and a model for
        batch evaluation and :mod:`brdfpy.checks`. It evaluates as :meth:`eval`, one sample at a time (the
        warp inversion has no vectorised form), and shares the material."""
        return Model("rgl_bsdf", _table=self._inner)

    def to_anisotropic(self, dims: tuple[int, int, int, int]) -> AnisotropicTabulated:
        """Resample the material onto an :class:`AnisotropicTabulated` table (:meth:`eval` at the bin centres,
        normal ``+z``, tangent ``+x``)."""
        return AnisotropicTabulated._wrap(self._inner.to_anisotropic(_dims("dims", dims)))

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rgl_from_bytes, (self.to_bytes(),))

    def to_tabulated(self, resolution: tuple[int, int, int] = (90, 90, 180)) -> Tabulated:
        """Resample an isotropic material onto a half/difference :class:`Tabulated` table (:meth:`eval` at the
        nodes); anisotropic materials are refused."""
        return Tabulated._wrap(self._inner.to_tabulated(_resolution("resolution", resolution)))

    def __repr__(self) -> str:
        return repr(self._inner)


def _rgl_from_bytes(data: bytes) -> RglBsdf:
    return RglBsdf.from_bytes(data)


#: The losses :func:`fit` minimises (``brdf_core::fit::Loss``; formulas and sources in :func:`fit`).
LOSSES = ("log", "cube_root", "cosine_relative", "linear")

#: How :func:`fit` draws samples from a table: ``"cosine"`` (default) or ``"half_diff"``.
STRATEGIES = ("cosine", "half_diff")

#: The keys the report of earlier versions (a dict) had: ``report[key]`` still reads them.
_LEGACY_KEYS = ("model", "values", "rms_log_error", "epsilon", "iterations", "converged", "samples_used")


@dataclass(frozen=True)
class ChannelError:
    """Error figures of one RGB channel at the solution of a fit."""

    #: Root-mean-square of the residuals of the loss (weights included).
    rms: float
    #: Largest absolute residual.
    max: float
    #: ``sqrt(sum (f - d)^2 / sum d^2)`` over the samples: the relative L2 error of the values.
    relative_l2: float


@dataclass(frozen=True)
class FitReport:
    """What :func:`fit` returns: the fitted model and how good the fit is.

    ``report["values"]``, ``report["converged"]`` and the other keys of the dict earlier versions returned
    (:data:`_LEGACY_KEYS`) still read the same numbers.
    """

    #: The fitted :class:`brdfpy.Model`, ready to render.
    model: Model
    #: The fitted values of the free parameters (float, or a 3-tuple for a colour).
    params: dict[str, Any]
    #: Their standard errors, ``sqrt(diag((J^T J)^-1) sigma^2)`` at the solution (NaN at a bound): right when
    #: every residual has the same spread (additive noise under the linear loss).
    stderr: dict[str, Any]
    #: The sandwich (heteroscedasticity-consistent; Huber 1967, White 1980) standard errors, right also when
    #: the spread varies (e.g. multiplicative noise under the log loss).
    stderr_robust: dict[str, Any]
    #: Per RGB channel error figures.
    errors: tuple[ChannelError, ChannelError, ChannelError]
    #: Free values that ended on a bound: ``(name or name[channel], bound)``.
    at_bound: list[tuple[str, float]]
    #: Continuous parameters held at their defaults because they do not change the model.
    inactive: list[str]
    #: The discrete choices of the best combination when ``choices`` were searched.
    choices: dict[str, str]
    #: The cost of every combination tried (``([(name, value), ...], cost)``; empty without a search).
    tried: list[tuple[list[tuple[str, str]], float]]
    #: The loss minimised and its value ``0.5 * sum r^2`` at the solution.
    loss: str
    cost: float
    #: RMS of ``ln(f + eps) - ln(d + eps)``, ``eps = 0.01 * mean(d)`` (the figure of earlier versions).
    rms_log_error: float
    epsilon: float
    #: Iterations of the final run, whether it converged and why it stopped.
    iterations: int
    converged: bool
    message: str
    #: Samples used (both directions above the surface) and starts tried.
    samples_used: int
    starts: int
    #: ``"analytic"`` or ``"finite_difference"``: how the Jacobian was computed.
    jacobian: str

    @property
    def values(self) -> dict[str, Any]:
        """The fitted parameters (:attr:`params`; the name of earlier versions)."""
        return self.params

    def keys(self) -> tuple[str, ...]:
        """The keys of the dict earlier versions returned (``dict(report)`` gives that dict)."""
        return _LEGACY_KEYS

    def __getitem__(self, key: str) -> Any:
        if key not in _LEGACY_KEYS:
            raise KeyError(key)
        return getattr(self, key)

    def __repr__(self) -> str:
        def fmt(x: Any) -> str:
            if isinstance(x, tuple):
                return "(" + ", ".join(f"{y:.4g}" for y in x) + ")"
            return f"{x:.4g}"

        lines = [f"FitReport({self.model.name}, loss={self.loss!r}: {self.message})"]
        for k, x in self.params.items():
            lines.append(f"  {k:<12} = {fmt(x)}  ± {fmt(self.stderr[k])}")
        if self.choices:
            lines.append("  choices: " + ", ".join(f"{k}={v}" for k, v in self.choices.items()))
        e = self.errors
        lines.append("  relative L2 error (R, G, B): " + ", ".join(f"{c.relative_l2:.3g}" for c in e))
        lines.append("  RMS loss residual (R, G, B): " + ", ".join(f"{c.rms:.3g}" for c in e))
        if self.at_bound:
            lines.append("  at a bound: " + ", ".join(f"{n} = {b:g}" for n, b in self.at_bound))
        if self.inactive:
            lines.append("  inactive (held at defaults): " + ", ".join(self.inactive))
        lines.append(
            f"  {self.iterations} iterations, {self.starts} starts, {self.samples_used} samples, "
            f"{self.jacobian} Jacobian"
        )
        return "\n".join(lines)


#: The type of :func:`fit`'s result under its former name.
FitResult = FitReport


def _mapping(name: str, m: object) -> dict[str, Any]:
    if m is None:
        return {}
    if not isinstance(m, Mapping):
        raise TypeError(f"{name}: expected a mapping of parameter names to values, got {type(m).__name__}")
    for k in m:
        if not isinstance(k, str):
            raise TypeError(f"{name}: parameter names must be strings, got {k!r}")
    return _plain(dict(m))


def fit(
    model: str,
    data: Tabulated | AnisotropicTabulated | tuple[ArrayLike, ArrayLike, ArrayLike, ArrayLike] | ArrayLike,
    v: ArrayLike | None = None,
    n: ArrayLike | None = None,
    values: ArrayLike | None = None,
    *,
    fixed: Mapping[str, ParamValue] | None = None,
    start: Mapping[str, ParamValue] | None = None,
    loss: str = "log",
    weights: ArrayLike | None = None,
    choices: Mapping[str, Sequence[str]] | None = None,
    multistart: int = 8,
    samples: int = 20_000,
    seed: int = 0,
    max_theta: float = 80.0,
    strategy: str = "cosine",
    max_iterations: int = 100,
    jacobian: str = "auto",
    tangent: ArrayLike | None = None,
) -> FitReport:
    """Fit registry model ``model`` to measured data: ``fit("cook_torrance", table)``.

    Every continuous parameter (scalars and RGB colours, each channel on its own, within its registry range)
    is free unless ``fixed``; parameters that do not change the model under the given choices (e.g. the
    conductor's ``eta`` with Schlick's Fresnel, a second lobe of weight 0) are held at their defaults and
    listed in :attr:`FitReport.inactive`. With no ``start``, the fit starts from the defaults and from
    ``multistart`` points of a deterministic Latin hypercube over the ranges and keeps the best. The solver
    is Levenberg–Marquardt (analytic Jacobian where one is written, see ``jacobian``), in Rust, in parallel,
    without the GIL; the result does not depend on the thread count.

    Parameters
    ----------
    model : str
        A registry name (see :func:`brdfpy.models`).
    data : Tabulated, AnisotropicTabulated, or (l, v, n, values)
        A table (sampled by ``strategy``: ``samples`` pairs of directions from ``seed``, both below
        ``max_theta`` degrees; see below; an :class:`AnisotropicTabulated` in its own frame, normal ``+z`` and
        tangent ``+x``, which then orients an anisotropic model), or arrays ``l, v, n`` of shape ``(..., 3)``
        that broadcast and
        ``values`` (measured ``f_r`` [1/sr], finite and ``>= 0``), as a tuple or as four positional
        arguments ``fit(model, l, v, n, values)``. Samples below the surface are dropped.
    fixed : mapping, optional
        Parameters held at the given values (choices such as ``distribution`` go here).
    start : mapping, optional
        Starting values of free parameters (a parameter named here is always fitted).
    loss : str
        With ``c = n·l``, model ``f`` and data ``d``: ``"log"`` (default) ``ln(1 + c f) − ln(1 + c d)``, the
        logarithmic metric of Löw, Kronander, Ynnerman & Unger (ACM ToG 31(1), 2012), relative near the peak
        and absolute in the dark tail; ``"cube_root"`` ``(c f)^(1/3) − (c d)^(1/3)``, the metric Forés,
        Ferwerda & Gu (Color and Imaging Conference 2012) found closest to perceived differences;
        ``"cosine_relative"`` ``c (f − d)/(d + ε)``, ``ε = 0.01·mean(d)``, the cosine-weighted error of Ngan,
        Durand & Matusik (EGSR 2005) made relative; ``"linear"`` ``f − d``.
    weights : array_like, optional
        A weight ``>= 0`` per sample (its residuals are multiplied by ``sqrt(w)``).
    choices : mapping of str to list of str, optional
        Discrete choices to search, e.g. ``{"distribution": ["ggx", "beckmann"]}``: every combination is
        fitted and the lowest cost kept (:attr:`FitReport.tried` lists them).
    multistart : int
        Latin-hypercube starts besides the given one (0 to 1024; 0: the given start only).
    samples, seed, max_theta, strategy
        How a table is sampled: ``"cosine"`` draws ``l`` and ``v`` independently, cosine-distributed over the
        hemisphere cut at ``max_theta`` (default 80°, the cut-off of Ngan et al. 2005); ``"half_diff"`` draws
        uniformly in the table's index coordinates (as dense near the specular peak as the MERL grid), keeping
        pairs below the cut-off (for an anisotropic table with a uniform azimuth of the half vector, so that
        every orientation of the lobe is drawn). Ignored for arrays.
    max_iterations : int
        Most iterations of the final run.
    jacobian : str
        ``"auto"`` (default): analytic for Lambert and for Cook–Torrance with GGX, Smith masking and Schlick's
        Fresnel (checked against central differences in the tests), central differences otherwise;
        ``"finite_difference"``: central differences always.
    tangent : array_like, optional
        With arrays: the tangent of each sample (``(..., 3)``, broadcast with ``l``), orienting an anisotropic
        model; without it, the arbitrary frame of each normal (tangent ``+x`` for ``n = +z``).

    Returns
    -------
    FitReport
    """
    if not isinstance(model, str):
        raise TypeError(f"model: expected a registry model name (str), got {type(model).__name__}")
    for name, k, lo, hi in (
        ("max_iterations", max_iterations, 1, 100_000),
        ("multistart", multistart, 0, 1024),
    ):
        if isinstance(k, bool) or not isinstance(k, int) or not lo <= k <= hi:
            raise ValueError(f"{name}: expected an integer in [{lo}, {hi}], got {k!r}")
    if not isinstance(loss, str) or loss not in LOSSES:
        raise ValueError(f"loss: expected one of {', '.join(LOSSES)}, got {loss!r}")
    ta: NDArray[np.float32] | None = None
    if isinstance(data, (Tabulated, AnisotropicTabulated)):
        if tangent is not None:
            raise TypeError("tangent: a table is sampled in its own frame; give tangents with arrays only")
        if v is not None or n is not None or values is not None:
            raise TypeError("v, n, values: give a table alone, or the arrays l, v, n, values")
        if not isinstance(strategy, str) or strategy not in STRATEGIES:
            raise ValueError(f"strategy: expected one of {', '.join(STRATEGIES)}, got {strategy!r}")
        theta = (
            float(max_theta)
            if isinstance(max_theta, (int, float)) and not isinstance(max_theta, bool)
            else None
        )
        if theta is None or not 0.0 < theta <= 90.0:
            raise ValueError(f"max_theta: expected degrees in (0, 90], got {max_theta!r}")
        if isinstance(data, AnisotropicTabulated):
            la, va, fa = _brdfpy.aniso_table_samples(data._inner, samples, seed, theta, strategy)
            ta = np.array([1.0, 0.0, 0.0], dtype=np.float32)
        else:
            la, va, fa = _brdfpy.table_samples(data._inner, samples, seed, theta, strategy)
        na = np.array([0.0, 0.0, 1.0], dtype=np.float32)
    else:
        if v is None and n is None and values is None:
            if not isinstance(data, (tuple, list)) or len(data) != 4:
                raise TypeError(
                    "data: expected a measured.Tabulated, an AnisotropicTabulated or a tuple "
                    "(l, v, n, values), "
                    f"got {type(data).__name__}"
                )
            l_, v_, n_, f_ = data
        elif v is None or n is None or values is None:
            raise TypeError("v, n, values: give all of l, v, n, values (or a table, or one tuple)")
        else:
            l_, v_, n_, f_ = data, v, n, values
        la, va, na = as_vectors("l", l_), as_vectors("v", v_), as_vectors("n", n_)
        fa = as_vectors("values", f_)
        ta = None if tangent is None else as_vectors("tangent", tangent)
    w = None
    if weights is not None:
        w = np.ascontiguousarray(_as_numeric("weights", weights), dtype=np.float64)
        if w.ndim != 1:
            raise ValueError(f"weights: expected one weight per sample (a 1-D array), got shape {w.shape}")
    fixed_d, start_d = _mapping("fixed", fixed), _mapping("start", start)
    choices_d: dict[str, list[str]] = {}
    if choices is not None:
        if not isinstance(choices, Mapping):
            raise TypeError(
                f"choices: expected a mapping of choice names to lists, got {type(choices).__name__}"
            )
        for cname, vals in choices.items():
            if isinstance(vals, str) or not isinstance(vals, Sequence):
                raise TypeError(f"choices: {cname!r} must map to a list of names, got {vals!r}")
            choices_d[cname] = list(vals)
    if jacobian not in ("auto", "finite_difference"):
        raise ValueError(f"jacobian: expected 'auto' or 'finite_difference', got {jacobian!r}")
    r = _brdfpy.fit_model(
        model,
        la,
        va,
        na,
        fa,
        w,
        fixed_d,
        start_d,
        loss,
        multistart,
        choices_d,
        max_iterations,
        jacobian,
        tangent=ta,
    )
    params: dict[str, Any] = dict(r["values"])
    chosen: dict[str, str] = dict(r["choices"])
    return FitReport(
        model=_model(model, **fixed_d, **chosen, **params),
        params=params,
        stderr=dict(r["stderr"]),
        stderr_robust=dict(r["stderr_robust"]),
        errors=tuple(ChannelError(*c) for c in r["channels"]),  # type: ignore[arg-type]
        at_bound=[(str(a), float(b)) for a, b in r["at_bound"]],
        inactive=list(r["inactive"]),
        choices=chosen,
        tried=[(list(c), float(x)) for c, x in r["tried"]],
        loss=str(r["loss"]),
        cost=float(r["cost"]),
        rms_log_error=float(r["rms_log_error"]),
        epsilon=float(r["epsilon"]),
        iterations=int(r["iterations"]),
        converged=bool(r["converged"]),
        message=str(r["message"]),
        samples_used=int(r["samples_used"]),
        starts=int(r["starts"]),
        jacobian=str(r["jacobian"]),
    )


def _plain(d: dict[str, Any]) -> dict[str, Any]:
    # NumPy scalars and arrays → Python numbers and lists, which the compiled module extracts.
    return {k: (x.tolist() if isinstance(x, (np.ndarray, np.generic)) else x) for k, x in d.items()}


@dataclass(frozen=True)
class Comparison:
    """A fit against its data (see :func:`compare`)."""

    #: ``f_r`` of the table and of the model over ``(θ_h, θ_d)`` at one ``φ_d``
    #: (:func:`brdfpy.views.half_diff_slice`).
    data_slice: HalfDiffSlice
    model_slice: HalfDiffSlice
    #: ``ln(1 + f_model) − ln(1 + f_data)`` per RGB channel, ``(n_d, n_h, 3)``; 0 where not :attr:`valid`.
    log_error: NDArray[np.float32]
    #: ``(f_model − f_data)/f_data`` per channel where the data are above 1e-6 of their largest value, else 0.
    relative_error: NDArray[np.float32]
    #: Where both directions are above the surface, ``(n_d, n_h)``.
    valid: NDArray[np.bool_]
    #: Directional albedo curves of both (:func:`brdfpy.views.albedo`).
    data_albedo: Albedo
    model_albedo: Albedo
    #: The lit spheres side by side, data on the left, model on the right, tone-mapped together.
    spheres: Image


def compare(
    table: Tabulated,
    model: Model | FitReport,
    *,
    phi_d: float = 90.0,
    size: int | tuple[int, int] = 90,
    sphere_size: int = 256,
    theta_i: ArrayLike | None = None,
) -> Comparison:
    """Compare a table with a model (or the model of a :class:`FitReport`): error maps over Rusinkiewicz's
    ``(θ_h, θ_d)`` at ``φ_d`` [deg] (``size`` cells, as :func:`brdfpy.views.half_diff_slice`), the directional
    albedo of both at ``theta_i`` [deg] (:func:`brdfpy.views.albedo`), and the lit spheres of both
    (:func:`brdfpy.views.lit_sphere`, ``sphere_size`` pixels each) side by side in one :class:`~brdfpy.Image`
    under one tone map (the extended Reinhard operator, white point at the brighter sphere's peak)."""
    from brdfpy import views

    if not isinstance(table, Tabulated):
        raise TypeError(f"table: expected a measured.Tabulated, got {type(table).__name__}")
    m = model.model if isinstance(model, FitReport) else model
    if not isinstance(m, _brdfpy.Model):
        raise TypeError(f"model: expected a brdfpy.Model or a FitReport, got {type(model).__name__}")
    tm = table.as_model()
    ds, ms = views.half_diff_slice([tm, m], phi_d=phi_d, size=size)
    valid = ds.valid & ms.valid
    fd, fm = ds.values.astype(np.float64), ms.values.astype(np.float64)
    log_err = np.where(valid[..., None], np.log1p(fm) - np.log1p(fd), 0.0).astype(np.float32)
    floor = 1e-6 * max(float(fd[valid].max(initial=0.0)), 1e-30)
    ok = valid[..., None] & (fd > floor)
    rel = np.where(ok, (fm - fd) / np.where(ok, fd, 1.0), 0.0).astype(np.float32)
    da, ma = views.albedo([tm, m], theta_i)
    first = views.lit_sphere([tm, m], size=sphere_size, tonemap="clamp")
    white = max(1.0, max(float(np.max(img.hdr)) for img in first))
    pair = views.lit_sphere([tm, m], size=sphere_size, tonemap="reinhard_extended", white=white)
    return Comparison(ds, ms, log_err, rel, valid, da, ma, _side_by_side(pair[0], pair[1]))


def _side_by_side(a: Image, b: Image) -> Image:
    """Two images of one height as one, ``a`` on the left (the buffers of both, tone-mapped as rendered)."""
    wa, ha, *bufs_a, tonemap, white, exposure = _brdfpy._frame_state(a._f)
    wb, hb, *bufs_b, _, _, _ = _brdfpy._frame_state(b._f)
    if ha != hb:
        raise ValueError(f"images of different heights ({ha}, {hb})")
    # The buffers are flat, row-major (an absent one is empty): join row by row.
    joined = []
    for x, y in zip(bufs_a, bufs_b):
        rows = np.concatenate([np.asarray(x).reshape(ha, wa, -1), np.asarray(y).reshape(hb, wb, -1)], axis=1)
        joined.append(np.ascontiguousarray(rows.reshape(-1)))
    hdr, depth, normal, ids, rgb8 = joined
    frame = _brdfpy._frame_from_state(wa + wb, ha, hdr, depth, normal, ids, rgb8, tonemap, white, exposure)
    return Image(frame)
