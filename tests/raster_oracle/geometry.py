"""Mesh geometry from seed 004 ("The Normal Vector", "Vertex Normal Vector for Polygonal Meshes") and
SCENE.md (the icosphere), plus the small meshes the tests build screens from. float64 throughout.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]


def _unit_rows(a: F64) -> F64:
    n = np.linalg.norm(a, axis=-1, keepdims=True)
    return np.divide(a, n, out=np.zeros_like(a), where=n > 0)


def face_cross(vertices: ArrayLike, faces: ArrayLike) -> F64:
    """Un-normalised face normals ``(v1 - v0) x (v2 - v0)`` (seed 004 eq. of "The Normal Vector (4)",
    written at v0); the length is twice the triangle's area (seed 004 "Approach 2")."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    return np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])


def newell(polygon: ArrayLike) -> F64:
    """Martin Newell's plane normal of a (possibly non-planar) polygon (seed 004 "The Normal Vector (5)"):
    ``a = sum (y_i - y_{i+1})(z_i + z_{i+1})`` and cyclically for b, c. Un-normalised."""
    p = np.asarray(polygon, dtype=np.float64)
    q = np.roll(p, -1, axis=0)
    x, y, z = p.T
    xn, yn, zn = q.T
    return np.array([np.sum((y - yn) * (z + zn)), np.sum((z - zn) * (x + xn)), np.sum((x - xn) * (y + yn))])


def corner_average(polygon: ArrayLike) -> F64:
    """Seed 004 method 1: the unit average of the unit normals ``(v_{i+1} - v_i) x (v_{i-1} - v_i)`` at
    every corner of a polygon."""
    p = np.asarray(polygon, dtype=np.float64)
    nxt, prv = np.roll(p, -1, axis=0), np.roll(p, 1, axis=0)
    corners = _unit_rows(np.cross(nxt - p, prv - p))
    s = corners.mean(axis=0)
    return s / np.linalg.norm(s)


def corner_angles(vertices: ArrayLike, faces: ArrayLike) -> F64:
    """(F, 3) interior angle of each triangle at each of its corners (seed 004 "Approach 3": arccos of
    the dot product of the unit edge vectors leaving the corner)."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    out = np.empty(f.shape)
    for k in range(3):
        a = v[f[:, k]]
        e1 = _unit_rows(v[f[:, (k + 1) % 3]] - a)
        e2 = _unit_rows(v[f[:, (k + 2) % 3]] - a)
        out[:, k] = np.arccos(np.clip(np.sum(e1 * e2, axis=1), -1.0, 1.0))
    return out


def vertex_normals(vertices: ArrayLike, faces: ArrayLike, weighting: str = "angle") -> F64:
    """Unit vertex normals as weighted sums over each vertex's star (seed 004 eqs. 12.31-12.33):
    ``equal`` sums unit face normals, ``area`` sums the cross products (2 x area), ``angle`` sums unit
    face normals times the corner angle. Vertices in no (non-degenerate) face get 0."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    cross = face_cross(v, f)
    unit = _unit_rows(cross)
    if weighting == "equal":
        w = np.repeat(unit[:, None, :], 3, axis=1)
    elif weighting == "area":
        w = np.repeat(cross[:, None, :], 3, axis=1)
    elif weighting == "angle":
        w = unit[:, None, :] * corner_angles(v, f)[:, :, None]
    else:
        raise ValueError(f"unknown weighting {weighting!r}")
    acc = np.zeros_like(v)
    for k in range(3):
        np.add.at(acc, f[:, k], w[:, k])
    return _unit_rows(acc)


# --------------------------------------------------------------------------------------- icosphere


def icosahedron() -> tuple[F64, I64]:
    """A regular icosahedron on the unit sphere (golden-ratio rectangles), faces CCW seen from outside."""
    t = (1 + 5**0.5) / 2
    v = np.array(
        [
            [-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0],
            [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
            [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1],
        ],
        dtype=np.float64,
    )  # fmt: skip
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    f = np.array(
        [
            [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
            [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
            [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
            [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
        ],
        dtype=np.int64,
    )  # fmt: skip
    return v, f


def subdivide(vertices: ArrayLike, faces: ArrayLike) -> tuple[F64, I64]:
    """One SCENE.md subdivision step: triangle (a, b, c) -> (a, ab, ca), (b, bc, ab), (c, ca, bc),
    (ab, bc, ca) where ``xy`` is the midpoint of x-y pushed onto the unit sphere; new vertices appended in
    ascending order of the edge key (min index, max index); children of face 0 first, then face 1, ..."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    edges = sorted({(min(a, b), max(a, b)) for tri in f.tolist() for a, b in zip(tri, tri[1:] + tri[:1])})
    index = {e: len(v) + i for i, e in enumerate(edges)}
    mids = np.array([(v[a] + v[b]) / 2 for a, b in edges]).reshape(-1, 3)
    mids /= np.linalg.norm(mids, axis=1, keepdims=True)

    def m(a: int, b: int) -> int:
        return index[(min(a, b), max(a, b))]

    out = []
    for a, b, c in f.tolist():
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        out += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
    return np.vstack([v, mids]), np.array(out, dtype=np.int64)


def icosphere(level: int, base: tuple[F64, I64] | None = None) -> tuple[F64, I64]:
    """The SCENE.md icosphere of ``level`` subdivisions of ``base`` (default :func:`icosahedron`)."""
    v, f = base if base is not None else icosahedron()
    for _ in range(level):
        v, f = subdivide(v, f)
    return v, f


# ----------------------------------------------------------------------------- screen-tiling meshes


def grid(nx: int, ny: int, jitter: float = 0.0, rng: np.random.Generator | None = None) -> tuple[F64, I64]:
    """A (nx+1) x (ny+1) vertex grid over [-1, 1]^2 at z = 0, each cell split into 2 triangles along an
    alternating diagonal, CCW seen from +z; interior vertices moved by up to ``jitter`` of a cell."""
    xs, ys = np.meshgrid(np.linspace(-1, 1, nx + 1), np.linspace(-1, 1, ny + 1))
    v = np.stack([xs, ys, np.zeros_like(xs)], axis=-1)
    if jitter and rng is not None:
        d = rng.uniform(-jitter, jitter, (ny - 1, nx - 1, 2)) * [2 / nx, 2 / ny]
        v[1:-1, 1:-1, :2] += d
    v = v.reshape(-1, 3)
    faces = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            b, c, d = a + 1, a + nx + 2, a + nx + 1
            faces += [[a, b, c], [a, c, d]] if (i + j) % 2 == 0 else [[a, b, d], [b, c, d]]
    return v, np.array(faces, dtype=np.int64)


def fan(
    center: ArrayLike, count: int, radius: float = 1.0, rng: np.random.Generator | None = None
) -> tuple[F64, I64]:
    """A triangle fan around ``center`` (z = 0) whose rim is a ``count``-gon of squares' corners pushed to
    the square [-radius, radius]^2, so the fan covers the whole square; angles jittered when ``rng``."""
    ang = np.linspace(0, 2 * np.pi, count, endpoint=False)
    if rng is not None:
        ang = np.sort(ang + rng.uniform(0, 0.5, count) * (2 * np.pi / count))
    # the square's corners must be rim vertices, or the fan would cut them off
    corners = np.array([np.pi / 4, 3 * np.pi / 4, 5 * np.pi / 4, 7 * np.pi / 4])
    ang = np.sort(np.concatenate([ang, corners]) % (2 * np.pi))
    ang = ang[np.concatenate([[True], np.diff(ang) > 1e-9])]
    d = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    rim = radius * d / np.max(np.abs(d), axis=1, keepdims=True)
    c = np.asarray(center, dtype=np.float64)[:2]
    v = np.vstack([[c[0], c[1], 0.0], np.column_stack([rim, np.zeros(len(rim))])])
    n = len(rim)
    f = np.array([[0, 1 + i, 1 + (i + 1) % n] for i in range(n)], dtype=np.int64)
    return v, f


def screen_tiling(
    kind: str, rng: np.random.Generator, camera: Any, aspect: float, depth: tuple[float, float] = (1.0, 4.0)
) -> tuple[F64, I64]:
    """A mesh whose image covers the whole screen exactly once, with many shared edges and vertices:
    a jittered ``"grid"`` or a ``"fan"`` around a random centre, drawn in NDC over a square of half-size
    1.5 turned by a random angle (so it covers the [-1, 1]^2 screen), then lifted along each vertex's
    camera ray to a random view depth in ``depth``. The lift keeps every vertex's image, so the triangles
    tile the screen as the 2-D pattern does, while in 3-D the mesh is a crumpled, non-planar sheet seen in
    perspective. Faces stay CCW on screen (front-facing)."""
    if kind == "grid":
        v, f = grid(int(rng.integers(9, 14)), int(rng.integers(7, 11)), 0.24, rng)
    else:
        v, f = fan(rng.uniform(-0.6, 0.6, 2), int(rng.integers(20, 40)), rng=rng)
    a = rng.uniform(0, 2 * np.pi)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    xy = 1.5 * v[:, :2] @ rot.T
    d = rng.uniform(depth[0], depth[1], len(v))
    return camera.unproject(xy, d, aspect), f


def rotation(axis: ArrayLike, angle: float) -> F64:
    """4x4 rotation by ``angle`` radians about ``axis`` (Rodrigues)."""
    k = np.asarray(axis, dtype=np.float64)
    k = k / np.linalg.norm(k)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    r = np.eye(4)
    r[:3, :3] = np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx
    return r


def translation(t: ArrayLike) -> F64:
    m = np.eye(4)
    m[:3, 3] = np.asarray(t, dtype=np.float64)
    return m


def scaling(s: float | ArrayLike) -> F64:
    m = np.eye(4)
    m[:3, :3] *= np.asarray(s, dtype=np.float64)
    return m
