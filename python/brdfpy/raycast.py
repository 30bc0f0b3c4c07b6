"""Ray queries against meshes: :class:`RayCaster`, a bounding volume hierarchy over triangles (binned-SAH
build, 4-wide tree, the watertight ray/triangle test of Woop, Benthin & Wald 2013) with batched closest-hit
and any-hit queries, and ambient obscurance at arbitrary points — the ray caster behind ``Scene.render``'s
``ao`` and ``shadows`` (``brdf-raster``'s ``bvh`` and ``ao`` modules).

Every query runs with the GIL released on brdfpy's thread pool (:func:`brdfpy.set_num_threads`); each ray and
each point is answered on its own, so results are bit-identical whatever the number of threads.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, NamedTuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import as_scalars, as_vec3
from brdfpy.mesh import Mesh, _mat4, _obscurance_args
from brdfpy.scene import Scene

__all__ = ["Hits", "RayCaster"]

Geometry = Union[Mesh, Scene, Sequence[Union[Mesh, tuple[Mesh, ArrayLike]]]]


class Hits(NamedTuple):
    """Closest hits of a batch of ``N`` rays (:meth:`RayCaster.closest_hit`)."""

    #: Ray parameter of the hit, float32 ``(N,)`` (the point ``origin + t·direction``); ``inf`` on a miss.
    t: NDArray[np.float32]
    #: Index of the triangle hit, int64 ``(N,)`` (see :class:`RayCaster` for the numbering); -1 on a miss.
    triangle: NDArray[np.int64]
    #: Barycentric weight of the triangle's second vertex, float32 ``(N,)``; 0 on a miss.
    u: NDArray[np.float32]
    #: Barycentric weight of the third vertex (the first has ``1 − u − v``), float32 ``(N,)``; 0 on a miss.
    v: NDArray[np.float32]

    @property
    def hit(self) -> NDArray[np.bool_]:
        """Whether each ray hit something, bool ``(N,)``."""
        return np.asarray(self.triangle >= 0)


def _parts(geometry: Any) -> list[tuple[_brdfpy.RasterMesh, list[float] | None]]:
    if isinstance(geometry, Scene):
        if not geometry.instances:
            raise ValueError("geometry: the scene has no meshes")
        return [(i.mesh._m, _mat4("transform", i.transform)) for i in geometry.instances]
    if isinstance(geometry, Mesh):
        return [(geometry._m, None)]
    if isinstance(geometry, (str, bytes)) or not isinstance(geometry, Sequence):
        raise TypeError(
            f"geometry: expected a Mesh, a Scene or a list of meshes / (mesh, transform) pairs, "
            f"got {type(geometry).__name__}"
        )
    out: list[tuple[_brdfpy.RasterMesh, list[float] | None]] = []
    for k, item in enumerate(geometry):
        if isinstance(item, tuple) and len(item) == 2:
            mesh, xf = item
            out.append((Mesh.from_any(mesh)._m, _mat4(f"geometry[{k}] transform", xf)))
        else:
            out.append((Mesh.from_any(item)._m, None))
    if not out:
        raise ValueError("geometry: is empty (need at least one mesh)")
    return out


def _bounds(name: str, x: ArrayLike) -> NDArray[np.float32]:
    a = as_scalars(name, x)
    if a.ndim > 1:
        raise ValueError(f"{name}: expected a number or an array of shape (N,), got shape {a.shape}")
    return np.ascontiguousarray(a.reshape(-1))


class RayCaster:
    """A bounding volume hierarchy over the triangles of a mesh, a scene or several meshes, for ray queries.

    Parameters
    ----------
    geometry : Mesh, Scene, or a list of Mesh / (Mesh, transform) pairs
        What rays can hit. A :class:`Scene` contributes every instance placed by its transform (world
        space, as rendered); a transform is a 4×4 matrix (column vectors, ``p' = M @ p``). Triangles are
        numbered through the meshes in order: triangle ``f`` of mesh ``k`` has id ``f + Σ_{j<k} F_j``.

    Notes
    -----
    Triangles are two-sided. Degenerate (zero-area) triangles are skipped, never hit (:attr:`n_skipped`
    counts them). The closest hit is the smallest ``t``; among hits at exactly the same ``t`` (a ray
    through a shared edge), the smallest triangle id — so the answer does not depend on the tree. The
    watertight test never lets a ray slip between two triangles that share an edge.

    The caster keeps its own copy of the triangles: later edits of the meshes do not reach it.

    Raises
    ------
    ValueError
        A mesh with a NaN vertex, a singular-free but non-finite transform, no meshes, or more triangles
        than the BVH can index (the message names the problem).

    Examples
    --------
    >>> rc = brdfpy.RayCaster(brdfpy.plane())  # the square y = 0, |x|, |z| <= 1
    >>> rc.closest_hit([0, 2, 0], [0, -1, 0]).t
    array([2.], dtype=float32)
    >>> rc.any_hit([[0, 2, 0], [5, 2, 0]], [0, -1, 0])
    array([ True, False])
    """

    __slots__ = ("_rc",)

    def __init__(self, geometry: Geometry) -> None:
        self._rc = _brdfpy.RayCaster(_parts(geometry))

    @property
    def n_triangles(self) -> int:
        """Number of input triangles (including skipped degenerate ones)."""
        return self._rc.n_triangles

    @property
    def n_skipped(self) -> int:
        """Number of degenerate (zero-area) input triangles, which no ray hits."""
        return self._rc.n_skipped

    @property
    def build_seconds(self) -> float:
        """Wall-clock time the BVH build took, in seconds."""
        return self._rc.build_seconds

    def bounds(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(min, max)`` corners of the box around every non-degenerate triangle."""
        lo, hi = self._rc.bounds()
        return np.array(lo, dtype=np.float64), np.array(hi, dtype=np.float64)

    def stats(self) -> dict[str, Any]:
        """Shape of the tree: ``nodes`` (4-wide), ``leaves``, ``max_leaf`` (triangles), ``max_depth`` and
        ``sah_cost`` (expected triangle tests per ray under the surface-area heuristic)."""
        return dict(self._rc.stats())

    def _rays(
        self, origins: ArrayLike, directions: ArrayLike, t_min: ArrayLike, t_max: ArrayLike
    ) -> tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32], NDArray[np.float32]]:
        o, _ = as_vec3("origins", origins)
        d, _ = as_vec3("directions", directions)
        return o, d, _bounds("t_min", t_min), _bounds("t_max", t_max)

    def closest_hit(
        self,
        origins: ArrayLike,
        directions: ArrayLike,
        t_min: ArrayLike = 0.0,
        t_max: ArrayLike = math.inf,
    ) -> Hits:
        """The first triangle along each ray ``origin + t·direction``, ``t ∈ [max(t_min, 0), t_max]``.

        Parameters
        ----------
        origins, directions : array_like, shape (N, 3) or (3,)
            Ray starts and directions (broadcast against each other). Directions need not be unit
            length; ``t`` is then in units of their length. They must be finite and non-zero.
        t_min, t_max : float or array_like (N,)
            The segment of each ray that counts (``t_max`` may be ``inf``, the default).

        Returns
        -------
        Hits
            ``(t, triangle, u, v)``, each of shape ``(N,)``; misses have ``t = inf`` and ``triangle = -1``.

        Raises
        ------
        ValueError
            Shapes that do not broadcast, NaN or infinite origins, zero or non-finite directions, NaN
            bounds (the message names the argument and the row).
        """
        t, tri, u, v = self._rc.closest_hit(*self._rays(origins, directions, t_min, t_max))
        return Hits(t, tri, u, v)

    def any_hit(
        self,
        origins: ArrayLike,
        directions: ArrayLike,
        t_min: ArrayLike = 0.0,
        t_max: ArrayLike = math.inf,
    ) -> NDArray[np.bool_]:
        """Whether anything lies on each ray segment (shadow / visibility rays), bool ``(N,)``.

        Same arguments and errors as :meth:`closest_hit`; it stops at the first triangle found, so it is
        faster. ``any_hit(...) == closest_hit(...).hit`` for every ray.
        """
        return self._rc.any_hit(*self._rays(origins, directions, t_min, t_max))

    def obscurance(
        self,
        points: ArrayLike,
        normals: ArrayLike,
        tau: float = 2.0,
        d_max: float | None = None,
        samples: int = 64,
        seed: int = 0,
    ) -> NDArray[np.float32]:
        """Ambient obscurance ``w`` at arbitrary points against everything in the caster.

        The estimate of :meth:`Mesh.compute_obscurance`, with the same parameters (``d_max`` defaults to a
        quarter of the diagonal of :meth:`bounds`), at ``points`` (N, 3) with unit ``normals`` (N, 3);
        point ``i`` uses the sample pattern keyed by ``(seed, i)``, so
        ``RayCaster(mesh).obscurance(mesh.vertices, mesh.normals)`` equals
        ``mesh.compute_obscurance()``. A zero normal gives 1 (no hemisphere). Returns float32 ``(N,)``.
        """
        p, _ = as_vec3("points", points)
        n, _ = as_vec3("normals", normals)
        if len(p) != len(n):
            raise ValueError(f"normals: {len(n)} rows for {len(p)} points")
        if d_max is None:
            lo, hi = self.bounds()
            d_max = 0.25 * float(np.linalg.norm(hi - lo)) if np.all(hi >= lo) else 1.0
        tau_, d_max_, samples_, seed_ = _obscurance_args(tau, d_max, samples, seed)
        return self._rc.obscurance(p, n, tau_, d_max_, samples_, seed_)

    def __repr__(self) -> str:
        return f"<brdfpy.RayCaster {self.n_triangles} triangles ({self.n_skipped} skipped)>"
