"""Triangle meshes for the rasterizer: from NumPy arrays, OBJ/PLY files, other libraries' meshes, procedural
shapes and the meshes embedded in the library.

Conventions: right-handed, +y up; faces are counter-clockwise seen from their front (outside) — the side
back-face culling keeps; vertex normals are unit length and point out of the front side.
"""

from __future__ import annotations

import copy
import os
import warnings
from typing import Any, Literal, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import _as_numeric, as_f64, as_str
from brdfpy._paths import as_path

__all__ = [
    "BUILTIN_MESHES",
    "ORIENT_MODES",
    "InwardMeshWarning",
    "Mesh",
    "builtin_mesh",
    "cube",
    "icosphere",
    "load_mesh",
    "open_box",
    "plane",
    "polygon_normal",
    "torus",
]

#: Names of the meshes embedded in the library, for :func:`builtin_mesh`.
BUILTIN_MESHES: tuple[str, ...] = tuple(_brdfpy.builtin_mesh_names())

PathLike = Union[str, "os.PathLike[str]"]

#: What :meth:`Mesh.from_any` and :func:`load_mesh` do with a closed mesh wound inward: ``"warn"`` (an
#: :class:`InwardMeshWarning` with the fix), ``"outward"`` (flip it) or ``"keep"`` (say nothing).
ORIENT_MODES: tuple[str, ...] = ("warn", "outward", "keep")
Orient = Literal["warn", "outward", "keep"]


class InwardMeshWarning(UserWarning):
    """A closed mesh whose faces are wound inward (negative signed volume): back-face culling keeps the
    inside of its far side, so it renders dark. :meth:`Mesh.flip_winding` fixes it."""


def _check_orient(orient: Any) -> str:
    if not isinstance(orient, str) or orient not in ORIENT_MODES:
        raise ValueError(f"orient: expected one of {', '.join(map(repr, ORIENT_MODES))}, got {orient!r}")
    return orient


def _apply_orient(mesh: Mesh, orient: str, source: str) -> Mesh:
    """``mesh`` checked (and flipped in place for ``"outward"``) by the rule of :data:`ORIENT_MODES`."""
    if orient == "keep" or not mesh.is_inward():
        return mesh
    if orient == "outward":
        return mesh.flip_winding()
    volume = mesh.stats()["signed_volume"]
    warnings.warn(
        f"{source}: the mesh is closed and its faces are wound inward (signed volume {volume:.4g} < 0), so "
        f"back-face culling shows its inside and it renders dark; fix: mesh.flip_winding() "
        f"(or load it with orient='outward')",
        InwardMeshWarning,
        stacklevel=3,
    )
    return mesh


_WEIGHTINGS = ("angle", "area", "equal")


def _rows(name: str, x: ArrayLike, dtype: type[np.generic], width: int = 3) -> NDArray[Any]:
    """``x`` as a C-contiguous ``(N, width)`` array of ``dtype``, with errors naming the argument."""
    if x is None:
        raise TypeError(f"{name}: expected an array of shape (N, {width}), got None")
    if isinstance(x, (str, bytes)):
        raise TypeError(f"{name}: expected an array of shape (N, {width}), got {type(x).__name__}")
    try:
        a = np.asarray(x)
    except (ValueError, TypeError) as e:
        raise ValueError(f"{name}: expected a rectangular array of numbers ({e})") from None
    if a.ndim != 2 or a.shape[1] != width:
        raise ValueError(f"{name}: expected shape (N, {width}), got {a.shape}")
    if a.shape[0] == 0:
        raise ValueError(f"{name}: is empty (shape {a.shape})")
    if dtype is np.uint32:
        if a.dtype.kind not in "iu":
            raise TypeError(f"{name}: expected integer vertex indices, got dtype {a.dtype}")
        if a.dtype.kind == "i" and (a < 0).any():
            row = int(np.argwhere(a < 0)[0, 0])
            raise ValueError(f"{name}: face {row} has a negative vertex index {a[row].tolist()}")
        if a.max() > np.iinfo(np.uint32).max:
            raise ValueError(f"{name}: vertex indices above 2^32 - 1 are not supported")
        return np.require(a, np.uint32, ["C", "A"])  # contiguous and aligned (e.g. a network buffer)
    if a.dtype.kind not in "fiu":
        raise TypeError(f"{name}: expected real numbers, got dtype {a.dtype}")
    with np.errstate(over="ignore", invalid="ignore"):
        out = np.require(a, np.float32, ["C", "A"])
    bad = ~np.isfinite(out).all(axis=1)
    if bad.any():
        row = int(np.argmax(bad))
        raise ValueError(f"{name}: row {row} is not finite (NaN, inf or beyond float32): {a[row].tolist()}")
    return out


def _readonly(a: NDArray[Any]) -> NDArray[Any]:
    a.flags.writeable = False
    return a


class Mesh:
    """A triangle mesh: vertex positions, unit vertex normals, faces (and optional vertex colors).

    Parameters
    ----------
    vertices : array_like, shape (V, 3)
        Vertex positions (any real dtype; stored as float32).
    faces : array_like of int, shape (F, 3)
        Vertex indices of each triangle, counter-clockwise seen from the front.
    normals : array_like, shape (V, 3), optional
        Vertex normals (normalised here; a zero normal is replaced by the computed one). Without them,
        normals are computed from the faces with angle weighting (see :meth:`compute_normals`).
    colors : array_like, shape (V, 3), optional
        Per-vertex linear RGB colors; they multiply the lit (not emitted) color in renders.
    uvs : array_like, shape (V, 2), optional
        Per-vertex texture coordinates, glTF's convention: ``(0, 0)`` is the top-left corner of the image,
        ``v`` grows downward (see :mod:`brdfpy.texture`). A material with textures needs them.
    tangents : array_like, shape (V, 4), optional
        Per-vertex tangents ``(t, w)`` as glTF's TANGENT: ``t`` along increasing ``u``, bitangent
        ``w·(n × t)`` up the image, ``w = ±1``. A normal map needs them; :meth:`with_generated_tangents`
        computes them (MikkTSpace).

    Raises
    ------
    ValueError
        Empty arrays, wrong shapes, NaN/inf values, or a face indexing past the vertices (the message
        names the argument and the face).
    TypeError
        Non-numeric arrays, or non-integer faces.

    Notes
    -----
    The arrays are copied into the library; :attr:`vertices`, :attr:`faces` and :attr:`normals` return
    read-only copies. Degenerate (zero-area) faces are kept and simply cover no pixel. A scene holds the
    mesh as it was when added: later :meth:`compute_normals` or :meth:`flip_winding` calls do not change
    scenes it was already added to.

    Examples
    --------
    >>> m = brdfpy.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> m.normals[0]
    array([0., 0., 1.], dtype=float32)
    """

    __slots__ = ("_m", "_w")

    _m: _brdfpy.RasterMesh
    # Stored per-vertex obscurance (read-only float32 (V,)) or None; see :attr:`obscurance`.
    _w: NDArray[np.float32] | None

    def __init__(
        self,
        vertices: ArrayLike,
        faces: ArrayLike,
        normals: ArrayLike | None = None,
        *,
        colors: ArrayLike | None = None,
        uvs: ArrayLike | None = None,
        tangents: ArrayLike | None = None,
    ) -> None:
        v = _rows("vertices", vertices, np.float32)
        f = _rows("faces", faces, np.uint32)
        if int(f.max()) >= len(v):
            row = int(np.argmax((f >= len(v)).any(axis=1)))
            raise ValueError(
                f"faces: face {row} {f[row].tolist()} indexes past the {len(v)} vertices "
                f"(valid indices are 0..{len(v) - 1})"
            )
        n = None if normals is None else _rows("normals", normals, np.float32)
        if n is not None and len(n) != len(v):
            raise ValueError(f"normals: {len(n)} rows for {len(v)} vertices")
        c = None if colors is None else _rows("colors", colors, np.float32)
        if c is not None and len(c) != len(v):
            raise ValueError(f"colors: {len(c)} rows for {len(v)} vertices")
        uv = None if uvs is None else _rows("uvs", uvs, np.float32, 2)
        if uv is not None and len(uv) != len(v):
            raise ValueError(f"uvs: {len(uv)} rows for {len(v)} vertices")
        t = None if tangents is None else _rows("tangents", tangents, np.float32, 4)
        if t is not None and len(t) != len(v):
            raise ValueError(f"tangents: {len(t)} rows for {len(v)} vertices")
        self._m = _brdfpy.RasterMesh(v, f, n, c, uv, t)
        self._w = None

    @classmethod
    def _wrap(cls, raw: _brdfpy.RasterMesh) -> Mesh:
        m = cls.__new__(cls)
        m._m = raw
        m._w = None
        return m

    @classmethod
    def from_any(cls, obj: Any, *, use_normals: bool = True, orient: Orient = "warn") -> Mesh:
        """A mesh from any object with ``.vertices`` and ``.faces`` (or ``.triangles``) arrays.

        Works with trimesh (``trimesh.Trimesh``), Open3D (``TriangleMesh``), meshio-like objects and plain
        namespaces, without importing any of them. A :class:`Mesh` is returned as it is (with
        ``orient="outward"``: a copy, flipped if it is wound inward).

        Parameters
        ----------
        obj
            The source mesh. Its ``vertex_normals`` (or ``normals``) are used when present, of the right
            shape and ``use_normals`` is true; otherwise normals are computed (angle weighting).
        use_normals : bool
            Take the object's vertex normals when it has them.
        orient : {"warn", "outward", "keep"}
            What to do when the mesh is closed and wound inward (:meth:`is_inward`, such as a trimesh mesh
            whose faces were reversed): warn with an :class:`InwardMeshWarning` naming the fix (default),
            flip it outward, or keep it silently.

        Raises
        ------
        TypeError
            If ``obj`` has no vertices or no faces.
        """
        mode = _check_orient(orient)
        if isinstance(obj, Mesh):
            return obj.copy().orient_outward() if mode == "outward" else obj
        vertices = getattr(obj, "vertices", None)
        faces = getattr(obj, "faces", None)
        if faces is None:
            faces = getattr(obj, "triangles", None)
        if vertices is None or faces is None:
            raise TypeError(
                f"obj: expected an object with .vertices and .faces (or .triangles) arrays, "
                f"got {type(obj).__name__}"
            )
        normals = None
        if use_normals:
            for attr in ("vertex_normals", "normals"):
                cand = getattr(obj, attr, None)
                if cand is None or callable(cand):
                    continue
                try:
                    arr = np.asarray(cand)
                except (ValueError, TypeError):
                    continue
                if arr.shape == np.shape(vertices) and arr.size > 0:
                    normals = arr
                    break
        colors = None
        visual = getattr(obj, "visual", None)
        vc = getattr(visual, "vertex_colors", None) if visual is not None else None
        if vc is not None:
            try:
                arr = np.asarray(vc)
            except (ValueError, TypeError):
                arr = np.empty((0,))
            if arr.ndim == 2 and arr.shape[0] == np.shape(vertices)[0] and arr.shape[1] in (3, 4):
                rgb = arr[:, :3].astype(np.float32)
                if arr.dtype.kind in "iu":
                    rgb /= 255.0
                # sRGB-encoded 8-bit colors → linear.
                colors = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
        mesh = cls(np.asarray(vertices), np.asarray(faces), normals, colors=colors)
        return _apply_orient(mesh, mode, f"obj ({type(obj).__name__})")

    # -- data -------------------------------------------------------------------------------------------

    @property
    def vertices(self) -> NDArray[np.float32]:
        """Vertex positions, float32 (V, 3) (a read-only copy)."""
        return _readonly(self._m.vertices)

    @property
    def faces(self) -> NDArray[np.uint32]:
        """Vertex indices of each triangle, uint32 (F, 3), counter-clockwise from the front (a copy)."""
        return _readonly(self._m.faces)

    @property
    def normals(self) -> NDArray[np.float32]:
        """Unit vertex normals, float32 (V, 3) (a read-only copy)."""
        return _readonly(self._m.normals)

    @property
    def colors(self) -> NDArray[np.float32] | None:
        """Per-vertex linear RGB colors, float32 (V, 3), or ``None``."""
        c = self._m.colors
        return None if c is None else _readonly(c)

    @property
    def uvs(self) -> NDArray[np.float32] | None:
        """Per-vertex texture coordinates, float32 (V, 2) (glTF's convention, ``v`` down), or ``None``."""
        u = self._m.uvs
        return None if u is None else _readonly(u)

    @property
    def tangents(self) -> NDArray[np.float32] | None:
        """Per-vertex tangents ``(t, w)``, float32 (V, 4), or ``None``."""
        t = self._m.tangents
        return None if t is None else _readonly(t)

    def with_generated_tangents(self) -> Mesh:
        """A copy with MikkTSpace tangents (Mikkelsen 2008, what glTF prescribes for normal maps) computed
        from the positions, normals and :attr:`uvs`; the mesh itself when it has tangents.

        Raises
        ------
        ValueError
            If the mesh has no texture coordinates.
        """
        if self._m.tangents is not None:
            return self
        m = Mesh._wrap(self._m.with_generated_tangents())
        m._w = self._w
        return m

    @property
    def n_vertices(self) -> int:
        """Number of vertices."""
        return self._m.n_vertices

    @property
    def n_faces(self) -> int:
        """Number of triangles."""
        return self._m.n_faces

    def __len__(self) -> int:
        return self._m.n_faces

    def __reduce__(self) -> tuple[Any, ...]:
        # Pickled as its arrays (out-of-band buffers under pickle protocol 5, as Dask sends them) and
        # rebuilt with the same bits: the stored normals are not normalised a second time.
        if self._m.uvs is not None or self._m.tangents is not None:
            return (
                _rebuild_textured_mesh,
                (self.vertices, self.faces, self.normals, self.colors, self.uvs, self.tangents, self._w),
            )
        return (_rebuild_mesh, (self.vertices, self.faces, self.normals, self.colors, self._w))

    def __repr__(self) -> str:
        lo, hi = self._m.bounds()
        box = " × ".join(f"{h - l:.3g}" for l, h in zip(lo, hi))
        return f"<brdfpy.Mesh {self.n_vertices} vertices, {self.n_faces} faces, size {box}>"

    def face_normals(self) -> NDArray[np.float32]:
        """Unit face normals, ``(p1 − p0) × (p2 − p0)`` normalised, float32 (F, 3); 0 if degenerate."""
        return self._m.face_normals()

    def bounds(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Axis-aligned bounding box ``(min, max)``, two arrays of 3."""
        lo, hi = self._m.bounds()
        return np.array(lo, dtype=np.float64), np.array(hi, dtype=np.float64)

    def bounding_sphere(self) -> tuple[NDArray[np.float64], float]:
        """``(center, radius)`` of a sphere enclosing every vertex (box centre, farthest vertex)."""
        c, r = self._m.bounding_sphere()
        return np.array(c, dtype=np.float64), float(r)

    def stats(self) -> dict[str, Any]:
        """Topology and geometry summary: counts, boundary / non-manifold / inconsistent edges, components,
        ``watertight``, ``winding_consistent``, ``signed_volume`` (> 0: outward CCW faces), ``area``,
        ``bounds``.
        """
        return dict(self._m.stats())

    # -- editing ----------------------------------------------------------------------------------------

    def compute_normals(self, weighting: str = "angle") -> Mesh:
        """Recompute the vertex normals from the faces, in place, and return ``self``.

        Each vertex normal is the normalised sum of the unit normals of its faces, weighted by (Theoharis,
        Papaioannou, Platis & Patrikalakis, *Graphics and Visualization: Principles & Algorithms*, 2008,
        eqs. 12.31–12.33):

        - ``"angle"``: the face's corner angle at the vertex (Thürmer & Wüthrich; independent of how a flat
          region is triangulated — the default);
        - ``"area"``: the face's area;
        - ``"equal"``: 1 (Gouraud's original average).
        """
        if not isinstance(weighting, str):
            raise TypeError(f"weighting: expected one of {_WEIGHTINGS}, got {type(weighting).__name__}")
        self._m.compute_normals(weighting)
        self._w = None  # the hemispheres have moved
        return self

    def is_inward(self) -> bool:
        """Whether the mesh is closed (watertight: every edge shared by exactly two faces) and wound
        inward: its signed volume ``Σ p₀·(p₁×p₂)/6`` is negative. Such a mesh renders dark (back-face
        culling keeps the inside of its far side) until :meth:`flip_winding`. An open mesh is never
        reported: its signed volume depends on the origin."""
        st = self._m.stats()
        return bool(st["watertight"]) and float(st["signed_volume"]) < 0

    def orient_outward(self) -> Mesh:
        """Flip the winding in place when :meth:`is_inward`; returns ``self``."""
        return self.flip_winding() if self.is_inward() else self

    def flip_winding(self) -> Mesh:
        """Reverse every face's winding and negate the normals, in place (for meshes wound inward, which
        back-face culling would otherwise hide); returns ``self``."""
        self._m.flip_winding()
        self._w = None  # the other side of the surface
        return self

    def transformed(self, matrix: ArrayLike) -> Mesh:
        """A new mesh with positions mapped by the 4×4 ``matrix`` (column vectors: ``p' = M @ p``) and
        normals by its inverse transpose."""
        return Mesh._wrap(self._m.transformed(_mat4("matrix", matrix)))

    def copy(self) -> Mesh:
        """An independent copy (with the stored :attr:`obscurance`, if any)."""
        # Copy-on-write: the data are shared until either mesh is changed in place.
        m = Mesh._wrap(copy.copy(self._m))
        m._w = self._w  # read-only, so sharing it is safe
        return m

    # -- ambient obscurance -----------------------------------------------------------------------------

    def compute_obscurance(
        self,
        tau: float = 2.0,
        d_max: float | None = None,
        samples: int = 64,
        seed: int = 0,
        *,
        store: bool = False,
    ) -> NDArray[np.float32]:
        """Per-vertex ambient obscurance ``w`` of the mesh against itself (Zhukov, Iones & Kronin 1998,
        in the form of Theoharis et al., *Graphics and Visualization*, 2008, eqs. 12.71–12.74).

        ::

            w(p) = (1/π) ∫_Ω μ(d(p, ω)) cos θ dω,
            μ(d) = (1 − e^(−τ d/d_max)) / (1 − e^(−τ))  for d < d_max,   μ(d) = 1 for d ≥ d_max,

        where ``d(p, ω)`` is the distance from vertex ``p`` to the first surface seen in direction ``ω`` of
        the hemisphere around its normal. ``μ`` is the book's ``1 − e^(−τx)`` with ``x = d/d_max``, rescaled
        so that it reaches 1 exactly at ``d_max``: ``w = 1`` for a vertex that sees nothing within
        ``d_max``, smaller the closer and the more surrounding surfaces are, 0 only where surfaces touch.

        It is estimated with ``samples`` cosine-weighted rays per vertex (a 2D Hammersley set, rotated per
        vertex by a hash of ``(seed, vertex index)``), so ``w`` is the mean of ``μ`` over the rays. Rays
        start a tiny offset along the normal to avoid re-hitting the vertex's own faces (see
        ``brdf-raster``'s ``ao.rs``). Runs in parallel with the GIL released; the result is
        bit-identical for any number of threads and the same for the same arguments.

        Parameters
        ----------
        tau : float
            ``τ > 0``, dimensionless (it applies to ``x = d/d_max``): how quickly an occluder's weight
            rises with its distance. Small τ makes ``μ`` nearly linear in ``d/d_max``; large τ confines
            the darkening to surfaces very close to the vertex. Default 2.
        d_max : float, optional
            ``d_max > 0``, in the mesh's own (object-space) units: surfaces farther than this do not
            obscure. Default: a quarter of the diagonal of the mesh's bounding box.
        samples : int
            Rays per vertex, 1–65536 (the Monte-Carlo error falls as ``1/√samples`` or faster). Default 64.
        seed : int
            Seed of the per-vertex rotations of the sample pattern, 0 ≤ seed < 2^64.
        store : bool
            Also keep the result as :attr:`obscurance`, which ``Scene.render(ao={"stored": True})`` uses
            instead of estimating ``w`` again.

        Returns
        -------
        numpy.ndarray
            ``w`` per vertex, float32 of shape ``(V,)``, in [0, 1]. Vertices with a zero normal (not used
            by any face) get 1.

        Raises
        ------
        ValueError
            ``tau`` or ``d_max`` not finite and > 0 (NaN included), ``samples`` out of range, ``seed``
            out of range; the message names the argument.
        TypeError
            Arguments that are not numbers / integers.

        Notes
        -----
        Only this mesh occludes (self-occlusion in object space). For occlusion by other objects use
        :meth:`brdfpy.RayCaster.obscurance` on the whole scene, or ``Scene.render(ao=...)``, which
        estimates ``w`` over the world-space scene.

        Examples
        --------
        >>> cow = brdfpy.builtin_mesh("cow")
        >>> w = cow.compute_obscurance(d_max=0.2, store=True)
        >>> w.shape, w.dtype, bool(w.min() >= 0 and w.max() <= 1)
        ((2904,), dtype('float32'), True)
        >>> scene = brdfpy.Scene()
        >>> inst = scene.add(cow, "lambert", ambient=0.3)  # the scene keeps the stored values
        >>> img = scene.render(brdfpy.Camera.perspective((0, 0, 2)), 320, 240, ao={"stored": True})
        """
        if d_max is None:
            lo, hi = self.bounds()
            d_max = max(0.25 * float(np.linalg.norm(hi - lo)), 1e-6)
        tau_, d_max_, samples_, seed_ = _obscurance_args(tau, d_max, samples, seed)
        w = _brdfpy.mesh_obscurance(self._m, tau_, d_max_, samples_, seed_)
        if store:
            self._w = _readonly(w.copy())
        return w

    @property
    def obscurance(self) -> NDArray[np.float32] | None:
        """Stored per-vertex obscurance ``w``, float32 ``(V,)`` in [0, 1] (read-only), or ``None``.

        Set by :meth:`compute_obscurance` with ``store=True``, or assigned directly (any ``(V,)`` array
        of values in [0, 1], e.g. baked elsewhere); ``None`` clears it. ``Scene.render(ao={"stored":
        True})`` interpolates it over the faces instead of estimating ``w``. It is cleared by
        :meth:`compute_normals` and :meth:`flip_winding` (which change the hemispheres it was
        computed over) and not carried over by :meth:`transformed`. A scene keeps the mesh as it was when
        added: store the values before ``Scene.add(mesh)``, or on the instance's own ``Instance.mesh``.
        """
        return self._w

    @obscurance.setter
    def obscurance(self, value: ArrayLike | None) -> None:
        if value is None:
            self._w = None
            return
        if isinstance(value, (str, bytes)):
            raise TypeError(f"obscurance: expected an array of shape (V,), got {type(value).__name__}")
        try:
            a = np.asarray(value)
        except (ValueError, TypeError) as e:
            raise ValueError(f"obscurance: expected an array of numbers ({e})") from None
        if a.dtype.kind not in "fiu":
            raise TypeError(f"obscurance: expected real numbers, got dtype {a.dtype}")
        if a.shape != (self.n_vertices,):
            raise ValueError(f"obscurance: expected shape ({self.n_vertices},), got {a.shape}")
        w = np.array(a, dtype=np.float32)
        bad = ~((w >= 0) & (w <= 1))  # NaN fails both comparisons
        if bad.any():
            i = int(np.argmax(bad))
            raise ValueError(f"obscurance: value {a[i]} at vertex {i} is not in [0, 1]")
        self._w = _readonly(w)


def _rebuild_mesh(
    vertices: NDArray[np.float32],
    faces: NDArray[np.uint32],
    normals: NDArray[np.float32],
    colors: NDArray[np.float32] | None,
    obscurance: NDArray[np.float32] | None,
) -> Mesh:
    # Buffers from the network may be unaligned: the compiled module reads aligned arrays only.
    def f32(a: NDArray[np.float32]) -> NDArray[np.float32]:
        return np.require(a, np.float32, ["C", "A"])

    ids = np.require(faces, np.uint32, ["C", "A"])
    raw = _brdfpy._mesh_from_parts(f32(vertices), ids, f32(normals), None if colors is None else f32(colors))
    m = Mesh._wrap(raw)
    m.obscurance = obscurance
    return m


def _rebuild_textured_mesh(
    vertices: NDArray[np.float32],
    faces: NDArray[np.uint32],
    normals: NDArray[np.float32],
    colors: NDArray[np.float32] | None,
    uvs: NDArray[np.float32] | None,
    tangents: NDArray[np.float32] | None,
    obscurance: NDArray[np.float32] | None,
) -> Mesh:
    m = Mesh(vertices, faces, normals, colors=colors, uvs=uvs, tangents=tangents)
    m.obscurance = obscurance
    return m


def _mat4(name: str, m: ArrayLike) -> list[float]:
    if m is None or isinstance(m, (str, bytes)):
        raise TypeError(f"{name}: expected a 4×4 matrix of numbers, got {type(m).__name__}")
    a = as_f64(name, m)  # complex, bool, object and ragged input refused naming it
    if a.shape != (4, 4):
        raise ValueError(f"{name}: expected shape (4, 4), got {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"{name}: contains a non-finite value")
    return [float(x) for x in a.reshape(16)]


def _check_int(name: str, x: Any, lo: int, hi: int | None = None) -> int:
    """An integer in ``[lo, hi]``; without ``hi``, one the compiled module takes as a 32-bit count (whose
    own limits then apply: beyond 2³² − 1 the conversion would raise ``OverflowError``)."""
    if isinstance(x, bool) or not isinstance(x, (int, np.integer)):
        raise TypeError(f"{name}: expected an integer, got {type(x).__name__}")
    v = int(x)
    if v < lo or v > (2**32 - 1 if hi is None else hi):
        rng = f">= {lo}" if hi is None else f"in [{lo}, {hi}]"
        raise ValueError(f"{name}: must be {rng}, got {v}")
    return v


def _check_pos(name: str, x: Any) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name}: expected a number, got {type(x).__name__}")
    v = float(x)
    if not (v > 0 and np.isfinite(v)):
        raise ValueError(f"{name}: must be finite and > 0, got {v}")
    return v


def _obscurance_args(tau: Any, d_max: Any, samples: Any, seed: Any) -> tuple[float, float, int, int]:
    """Checked ``(tau, d_max, samples, seed)`` for the obscurance estimators (errors name the argument)."""
    return (
        _check_pos("tau", tau),
        _check_pos("d_max", d_max),
        _check_int("samples", samples, 1, 65536),
        _check_int("seed", seed, 0, 2**64 - 1),
    )


def load_mesh(path: PathLike, *, up: str = "y", orient: Orient = "warn") -> Mesh:
    """Load a triangle mesh from an OBJ, PLY or STL file (chosen by the extension).

    OBJ polygons are triangulated (fan), PLY may be ASCII or binary with extra properties, STL binary or
    ASCII (corners at the same position are welded into one vertex; the file's facet normals are ignored);
    vertex normals and colors are used when the file has them, normals are computed (angle weighting) when
    not. For glTF scenes see :func:`brdfpy.load_scene`.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    up : {"y", "-y", "z", "-z", "x", "-x"}
        The file's up axis: the mesh is rotated by :func:`brdfpy.transforms.up_to_y` to stand in brdfpy's
        +y-up world (``"z"`` for CAD, 3D-printing and Blender exports, such as the Utah teapot).
    orient : {"warn", "outward", "keep"}
        A closed mesh wound inward (:meth:`Mesh.is_inward`) is reported by an :class:`InwardMeshWarning`
        (default), flipped outward, or kept silently.

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    ValueError
        An unknown extension, or a malformed, truncated or empty file (the message names the file).
    """
    p = as_path("path", path)
    if not os.path.exists(p):
        raise FileNotFoundError(f"path: no such file: {p!r}")
    if os.path.isdir(p):
        raise IsADirectoryError(f"path: is a directory: {p!r}")
    mode = _check_orient(orient)
    from brdfpy.transforms import up_to_y  # transforms imports camera, which needs no mesh

    stand = up_to_y(up)
    mesh = Mesh._wrap(_brdfpy.load_mesh(p))
    if up.strip().lower().lstrip("+") != "y":
        mesh = mesh.transformed(stand)
    return _apply_orient(mesh, mode, p)


def polygon_normal(points: ArrayLike, method: str = "newell") -> NDArray[np.float32]:
    """Normal of a planar or nearly planar polygon from its vertices in order (Theoharis et al. 2008, ch. 12).

    Parameters
    ----------
    points : array_like, shape (K, 3), K >= 3
        The vertices, counter-clockwise seen from the side the normal points to.
    method : {"newell", "cross", "corner_average"}
        ``"newell"``: Newell's method, ``n_x = Σ (y_i − y_{i+1})(z_i + z_{i+1})`` and cyclic; robust for
        non-planar and non-convex polygons; its length is twice the polygon's area.
        ``"cross"``: ``(p1 − p0) × (p2 − p0)``, the triangle normal at the first corner.
        ``"corner_average"``: the mean of the unit corner normals ``(p_{i+1} − p_i) × (p_{i−1} − p_i)``.

    Returns
    -------
    ndarray of float32, shape (3,)
        The (unnormalised) normal.
    """
    a = _as_numeric("points", points).astype(np.float64)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"points: expected shape (K, 3), got {a.shape}")
    n = _brdfpy.polygon_normal(a.tolist(), as_str("method", method, "a method name"))
    return np.asarray(n, dtype=np.float32)


def builtin_mesh(name: str) -> Mesh:
    """A mesh embedded in the library (no files needed), by name from :data:`BUILTIN_MESHES`:

    - ``"cow"``: Garland's QSlim cow (5,804 triangles), about 1 unit long along x;
    - ``"fandisk"``: Hoppe's fandisk CAD part (12,946 triangles, sharp creases), about 1 unit tall.

    Both are CC0 (from CGAL's data set).
    """
    if not isinstance(name, str):
        raise TypeError(f"name: expected a built-in mesh name (str), got {type(name).__name__}")
    return Mesh._wrap(_brdfpy.builtin_mesh(name))


def icosphere(level: int = 3) -> Mesh:
    """A unit sphere made by subdividing an icosahedron ``level`` times (0–10): ``20·4^level`` triangles,
    exact normals (= positions). The vertex and face order are those of the canonical benchmark scene."""
    return Mesh._wrap(_brdfpy.icosphere(_check_int("level", level, 0, 10)))


def torus(major_segments: int = 64, minor_segments: int = 32) -> Mesh:
    """A torus around the +z axis: ring radius 0.7, tube radius 0.3, exact normals,
    ``2·major_segments·minor_segments`` triangles."""
    return Mesh._wrap(
        _brdfpy.torus(
            _check_int("major_segments", major_segments, 3), _check_int("minor_segments", minor_segments, 3)
        )
    )


def plane(size: float = 2.0, subdivisions: int = 1) -> Mesh:
    """A square of side ``size`` in the plane y = 0, centred at the origin, facing +y (a floor), split into
    ``subdivisions × subdivisions`` cells of two triangles."""
    return Mesh._wrap(_brdfpy.plane(_check_pos("size", size), _check_int("subdivisions", subdivisions, 1)))


def cube(size: float = 1.0, subdivisions: int = 1) -> Mesh:
    """A closed cube of side ``size`` centred at the origin, with flat faces (no shared vertices)."""
    return Mesh._wrap(_brdfpy.cube(_check_pos("size", size), _check_int("subdivisions", subdivisions, 1)))


def open_box(size: float = 1.0, subdivisions: int = 1) -> Mesh:
    """A box open at the top (+y), faces pointing inward: a test scene for ambient occlusion."""
    return Mesh._wrap(_brdfpy.open_box(_check_pos("size", size), _check_int("subdivisions", subdivisions, 1)))
