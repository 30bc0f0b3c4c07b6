"""The reference rasterizer: one sample per pixel centre, float64, a Python loop over triangles.

Pipeline (SCENE.md conventions):

1. World space: ``p_w = M p``, normals by the inverse transpose of M's 3x3, re-normalised.
2. Clip space ``P V p_w``; near/far clipping (:mod:`raster_oracle.clip`) carrying each new vertex's
   barycentric coordinates *in the original triangle* (``beta``), so every attribute is later
   interpolated from the original three vertices.
3. Viewport: NDC x in [-1, 1] -> [0, W] columns, NDC y = +1 -> the top edge of row 0; pixel (c, r) is
   sampled at its centre (c + 0.5, r + 0.5). Vertex positions are snapped to ``1/2^subpixel_bits`` of a
   pixel (round to nearest), as a fixed-point rasterizer does.
4. Facing: CCW in NDC (y up) is the front. Zero-area triangles are skipped (they cover nothing).
5. Coverage by edge functions; a pixel centre exactly on an edge belongs to the triangle for which that
   edge is a *top* edge (horizontal, the triangle below it; the image's y grows downward) or a *left*
   edge (the triangle to its right) -- the top-left rule, so two triangles sharing an edge never both
   cover, and never both miss, a sample on it.
6. Depth: window depth ``(z_ndc + 1)/2``, linear in screen space; test "less"; cleared to 1.
7. Perspective-correct interpolation: screen barycentrics ``lambda_i`` -> ``(lambda_i / w_i) / sum``.
8. Shading (seed 004; SPEC row 14): ``c = emission + ka Ia + sum_j E_j shade(model, l_j, v, n)``:
   ``flat`` (seed 004 "Constant Shading": one value per facet from the geometric face normal at the
   centroid), ``gouraud`` (the illumination model at the vertices with the vertex normals, colours
   interpolated perspective-correctly), ``phong`` (normal and world position interpolated, normal
   re-normalised, the model applied per pixel; SCENE.md "Interpolation") and ``quadratic`` (as phong,
   but with van Overveld & Wyvill's quadratic normal, :func:`quadratic_normal`).

Besides the image, the frame records for each pixel how close its centre lies to an edge of a visible
triangle (``edge_dist``, pixels) and the depth gap to the nearest losing fragment (``depth_gap``): a
renderer that snaps or rounds differently may legitimately decide those pixels the other way.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from oracle import models as om
from oracle import tonemap as otm
from raster_oracle.camera import Camera
from raster_oracle.clip import clip_triangle
from raster_oracle.geometry import vertex_normals

F64 = NDArray[np.float64]


def _rgb(x: ArrayLike) -> F64:
    a = np.asarray(x, dtype=np.float64).reshape(-1)
    return np.repeat(a, 3) if a.size == 1 else a.reshape(3)


def _unit(a: F64) -> F64:
    n = np.linalg.norm(a, axis=-1, keepdims=True)
    return np.divide(a, n, out=np.zeros_like(a), where=n > 0)


@dataclass
class Material:
    """A registry model (``name`` with fully resolved ``params``), its ambient reflectance ``ka`` and
    its emission ``Ie`` (seed 004 eq. 12.28)."""

    model: str
    params: dict[str, Any]
    ambient: ArrayLike = 0.0
    emission: ArrayLike = 0.0


@dataclass
class Instance:
    vertices: ArrayLike
    faces: ArrayLike
    material: Material
    normals: ArrayLike | None = None
    transform: ArrayLike = field(default_factory=lambda: np.eye(4))
    #: optional per-vertex linear RGB colours (V, 3) tinting everything but the emission
    colors: ArrayLike | None = None


@dataclass
class Scene:
    instances: list[Instance]
    lights: list[Any]
    ambient_light: ArrayLike = 1.0
    background: ArrayLike = 0.0


@dataclass
class Frame:
    """Buffers, row 0 at the top. ``triangle_id``/``instance_id`` are -1 where nothing was drawn."""

    hdr: F64
    depth: F64
    normal: F64
    position: F64
    triangle_id: NDArray[np.int64]
    instance_id: NDArray[np.int64]
    edge_dist: F64
    depth_gap: F64
    #: per-pixel sensitivity of a buffer to the exact vertex positions (filled by the test bridge)
    sensitivity: dict[str, F64] = field(default_factory=dict)

    @property
    def covered(self) -> NDArray[np.bool_]:
        return self.triangle_id >= 0

    def ambiguous(self, edge_eps: float = 1 / 128, depth_eps: float = 1e-5) -> NDArray[np.bool_]:
        """Pixels whose centre is within ``edge_eps`` pixels of an edge of a visible triangle, or whose
        winning fragment is within ``depth_eps`` (window depth) of a losing one."""
        return (self.edge_dist < edge_eps) | (self.depth_gap < depth_eps)

    def rgb8(self, operator: str = "clamp") -> NDArray[np.uint8]:
        return otm.to_uint8(self.hdr, operator)


# ------------------------------------------------------------------------------------------ shading


def illuminate(
    material: Material,
    p: F64,
    n: F64,
    camera: Camera,
    lights: list[Any],
    ambient_light: ArrayLike,
    tint: F64 | None = None,
) -> F64:
    """Seed 004 eq. 12.28 / SPEC row 14 at points ``p`` with unit normals ``n`` (N, 3):
    ``emission + tint (ka Ia + sum_j E_j shade(model, l_j, v, n))``, ``v`` from the camera; ``tint``
    (N, 3) is the interpolated vertex colour (seed 004 12.28's "(r', g', b') = (r I_r, g I_g, b I_b)": the
    object's colour modifies the computed intensity), 1 without vertex colours."""
    v = camera.view_vector(p)
    out = np.broadcast_to(_rgb(material.ambient) * _rgb(ambient_light), p.shape).copy()
    for light in lights:
        l, e, _ = light.incident(p)
        s = om.evaluate(material.model, material.params, l, v, n, quantity="shade")
        out += e * s
    if tint is not None:
        out *= tint
    return out + _rgb(material.emission)


def quadratic_midnormals(p: F64, n: F64) -> F64:
    """The edge mid-control normals ``m_ij`` (ij = 01, 12, 20) of the quadratic normal field, for
    triangles with corners ``p`` and unit vertex normals ``n`` (..., 3, 3) -> (..., 3, 3).

    Seed 004 ("Quadratic Interpolation of Vertex Normals (3)", after van Overveld & Wyvill 1997) along
    one edge: ``n(s) = n0 + s a + s^2 b``, ``b = 3 ((n0 + n1).delta / delta^2) delta``,
    ``a = n1 - n0 - b``, delta = p1 - p0; in Bernstein form ``n0 (1-s)^2 + 2 m s(1-s) + n1 s^2`` with
    ``m = (n0 + n1)/2 - b/2``. (Its defining property: the mean of n(s) over the edge,
    ``(n0 + n1)/2 - b/6``, is perpendicular to the edge.)"""
    out = np.empty(np.broadcast_shapes(p.shape, n.shape))
    for k, (i, j) in enumerate(((0, 1), (1, 2), (2, 0))):
        d = p[..., j, :] - p[..., i, :]
        s = n[..., i, :] + n[..., j, :]
        b = 3.0 * (np.sum(s * d, axis=-1) / np.sum(d * d, axis=-1))[..., None] * d
        out[..., k, :] = s / 2 - b / 2
    return out


def quadratic_normal(beta: F64, p: F64, n: F64) -> F64:
    """The quadratic normal at barycentrics ``beta`` (N, 3) of triangles ``p``, ``n`` ((N, 3, 3) or one
    (3, 3)): the quadratic Bezier triangle whose corner controls are the unit vertex normals and whose
    edge controls are :func:`quadratic_midnormals`, ``sum b_i^2 n_i + 2 sum b_i b_j m_ij``,
    re-normalised. On every edge it is seed 004's 1-D formula; inside, the quadratic with those edges."""
    m = quadratic_midnormals(p, n)
    b0, b1, b2 = beta[:, 0:1], beta[:, 1:2], beta[:, 2:3]
    q = (
        b0**2 * n[..., 0, :]
        + b1**2 * n[..., 1, :]
        + b2**2 * n[..., 2, :]
        + 2 * (b0 * b1 * m[..., 0, :] + b1 * b2 * m[..., 1, :] + b2 * b0 * m[..., 2, :])
    )
    return _unit(q)


# ---------------------------------------------------------------------------------------- raster


@dataclass
class _Piece:
    inst: int
    face: int
    xy: F64  # (3, 2) snapped screen positions, ordered so the area is positive
    zw: F64  # (3,) window depth
    inv_w: F64  # (3,) 1/w_clip
    beta: F64  # (3, 3) barycentrics in the original triangle
    area: float


def _edges(xy: F64, px: F64, py: F64) -> list[F64]:
    """Edge functions E_12, E_20, E_01 at the points (px, py) (positive inside, for positive area)."""
    out = []
    for a, b in ((1, 2), (2, 0), (0, 1)):
        ax, ay = xy[a]
        bx, by = xy[b]
        out.append((bx - ax) * (py - ay) - (by - ay) * (px - ax))
    return out


def _owns_ties(xy: F64) -> list[bool]:
    """Top-left rule for the edges 12, 20, 01 (y down): with inside normal ``(-dy, dx)``, a left edge has
    a positive x component, a top edge a zero x and positive y component."""
    out = []
    for a, b in ((1, 2), (2, 0), (0, 1)):
        dx, dy = xy[b] - xy[a]
        nx, ny = -dy, dx
        out.append(bool(nx > 0 or (nx == 0 and ny > 0)))
    return out


def _segment_dist(xy: F64, px: F64, py: F64) -> F64:
    out = np.full(px.shape, np.inf)
    for a, b in ((1, 2), (2, 0), (0, 1)):
        d = xy[b] - xy[a]
        t = np.clip(((px - xy[a, 0]) * d[0] + (py - xy[a, 1]) * d[1]) / (d @ d), 0.0, 1.0)
        out = np.minimum(out, np.hypot(px - xy[a, 0] - t * d[0], py - xy[a, 1] - t * d[1]))
    return out


def _world(inst: Instance) -> tuple[F64, F64, NDArray[np.int64]]:
    v = np.asarray(inst.vertices, dtype=np.float64)
    f = np.asarray(inst.faces, dtype=np.int64).reshape(-1, 3)
    m = np.asarray(inst.transform, dtype=np.float64)
    pw = v @ m[:3, :3].T + m[:3, 3]
    if inst.normals is None:
        n = vertex_normals(v, f, "angle")
    else:
        n = np.asarray(inst.normals, dtype=np.float64)
    nw = _unit(n @ np.linalg.inv(m[:3, :3]))  # (M^-T n) as row vectors: n M^-1
    return pw, nw, f


def _setup(
    world: list[tuple[F64, F64, NDArray[np.int64]]],
    vp: F64,
    width: int,
    height: int,
    cull_back_faces: bool,
    subpixel_bits: int | None,
    jitter: tuple[float, np.random.Generator] | None = None,
) -> list[_Piece]:
    """Clip, project, snap, cull: the screen triangles in submission order. ``jitter = (amplitude, rng)``
    moves every snapped screen vertex by a uniform random offset (pixels) in each coordinate."""
    snap = None if subpixel_bits is None else float(2**subpixel_bits)
    pieces: list[_Piece] = []
    for k, (pw, _, faces) in enumerate(world):
        clip = np.column_stack([pw, np.ones(len(pw))]) @ vp.T
        for fi, face in enumerate(faces):
            for cpos, cbeta in clip_triangle(clip[face], np.eye(3)):
                w = cpos[:, 3]
                ndc = cpos[:, :3] / w[:, None]
                xy = np.column_stack([(ndc[:, 0] + 1) / 2 * width, (1 - ndc[:, 1]) / 2 * height])
                if snap is not None:
                    xy = np.round(xy * snap) / snap
                if jitter is not None:
                    xy = xy + jitter[1].uniform(-jitter[0], jitter[0], xy.shape)
                area = (xy[1, 0] - xy[0, 0]) * (xy[2, 1] - xy[0, 1]) - (xy[2, 0] - xy[0, 0]) * (
                    xy[1, 1] - xy[0, 1]
                )
                if area == 0:
                    continue
                front = area < 0  # CCW with y up is CW with y down
                if cull_back_faces and not front:
                    continue
                order = [0, 2, 1] if area < 0 else [0, 1, 2]
                pieces.append(
                    _Piece(k, fi, xy[order], (ndc[order, 2] + 1) / 2, 1 / w[order], cbeta[order], abs(area))
                )
    return pieces


def _cover(pc: _Piece, width: int, height: int) -> tuple[NDArray[np.int64], NDArray[np.int64], F64] | None:
    """Rows, columns and screen barycentrics (N, 3) of the pixel centres the piece covers."""
    lo = np.maximum(np.ceil(pc.xy.min(axis=0) - 0.5), 0).astype(int)
    hi = np.minimum(np.floor(pc.xy.max(axis=0) - 0.5), [width - 1, height - 1]).astype(int)
    if np.any(hi < lo):
        return None
    cs, rs = np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1)
    px, py = np.meshgrid(cs + 0.5, rs + 0.5)
    e = _edges(pc.xy, px, py)
    inside = np.ones(px.shape, dtype=bool)
    for ei, oi in zip(e, _owns_ties(pc.xy)):
        inside &= (ei > 0) | ((ei == 0) & oi)
    if not inside.any():
        return None
    lam = np.stack(e, axis=-1)[inside] / pc.area
    return py[inside].astype(np.int64), px[inside].astype(np.int64), lam


def coverage_count(
    vertices: ArrayLike,
    faces: ArrayLike,
    camera: Camera,
    width: int,
    height: int,
    transform: ArrayLike | None = None,
    cull_back_faces: bool = True,
    subpixel_bits: int | None = 8,
) -> NDArray[np.int64]:
    """How many triangles cover each pixel centre, ignoring depth (additive coverage)."""
    m = np.eye(4) if transform is None else np.asarray(transform, dtype=np.float64)
    v = np.asarray(vertices, dtype=np.float64)
    world = [(v @ m[:3, :3].T + m[:3, 3], v, np.asarray(faces, dtype=np.int64).reshape(-1, 3))]
    vp = camera.view_projection(width / height)
    count = np.zeros((height, width), dtype=np.int64)
    for pc in _setup(world, vp, width, height, cull_back_faces, subpixel_bits):
        got = _cover(pc, width, height)
        if got is not None:
            np.add.at(count, (got[0], got[1]), 1)
    return count


def render(
    scene: Scene,
    camera: Camera,
    width: int,
    height: int,
    shading: str = "phong",
    cull_back_faces: bool = True,
    subpixel_bits: int | None = 8,
    perspective_correct: bool = True,
    jitter: tuple[float, np.random.Generator] | None = None,
) -> Frame:
    """Render ``scene`` seen by ``camera`` into a ``height`` x ``width`` frame.

    ``perspective_correct=False`` interpolates affinely in screen space (the seed's scanline
    interpolation taken literally): only for showing that a test can tell the two apart. ``jitter``
    (amplitude in pixels, generator) perturbs the screen vertices after snapping: rendering twice with
    and without it measures how sensitive each pixel is to where exactly a renderer puts the vertices."""
    if shading not in ("flat", "gouraud", "phong", "quadratic"):
        raise ValueError(f"unknown shading {shading!r}")
    vp = camera.view_projection(width / height)
    world = [_world(inst) for inst in scene.instances]

    depth = np.ones((height, width))
    gap = np.full((height, width), np.inf)
    tri = np.full((height, width), -1, dtype=np.int64)
    ins = np.full((height, width), -1, dtype=np.int64)
    beta_buf = np.zeros((height, width, 3))
    pieces: list[_Piece] = []
    for pc in _setup(world, vp, width, height, cull_back_faces, subpixel_bits, jitter):
        pieces.append(pc)
        got = _cover(pc, width, height)
        if got is None:
            continue
        rr, cc, lam = got
        z = lam @ pc.zw
        cur = depth[rr, cc]
        gap[rr, cc] = np.minimum(gap[rr, cc], np.where(cur < 1, np.abs(z - cur), np.inf))
        win = z < cur
        rr, cc = rr[win], cc[win]
        depth[rr, cc] = z[win]
        tri[rr, cc] = pc.face
        ins[rr, cc] = pc.inst
        pl = lam[win] * pc.inv_w if perspective_correct else lam[win]
        pl /= pl.sum(axis=1, keepdims=True)
        beta_buf[rr, cc] = pl @ pc.beta

    # edges of the triangles that are visible at (or within 1 px of) a pixel, in a second pass
    edge = np.full((height, width), np.inf)
    for pc in pieces:
        lo = np.maximum(np.floor(pc.xy.min(axis=0) - 1.5), 0).astype(int)
        hi = np.minimum(np.ceil(pc.xy.max(axis=0) + 0.5), [width - 1, height - 1]).astype(int)
        if np.any(hi < lo):
            continue
        cs, rs = np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1)
        px, py = np.meshgrid(cs + 0.5, rs + 0.5)
        lam = np.stack(_edges(pc.xy, px, py), axis=-1) / pc.area
        z = lam @ pc.zw  # the triangle's plane, extended past its edges
        seen = z <= depth[rs[0] : rs[-1] + 1, cs[0] : cs[-1] + 1] + 1e-6
        d = np.where(seen, _segment_dist(pc.xy, px, py), np.inf)
        win = (slice(rs[0], rs[-1] + 1), slice(cs[0], cs[-1] + 1))
        edge[win] = np.minimum(edge[win], d)

    hdr = np.broadcast_to(_rgb(scene.background), (height, width, 3)).copy()
    normal = np.zeros((height, width, 3))
    position = np.zeros((height, width, 3))
    for k, (pw, nw, faces) in enumerate(world):
        mask = ins == k
        if not mask.any():
            continue
        inst = scene.instances[k]
        f = faces[tri[mask]]
        beta = beta_buf[mask]
        p = np.einsum("ni,nij->nj", beta, pw[f])
        cols = None if inst.colors is None else np.asarray(inst.colors, dtype=np.float64)
        tint = None if cols is None else np.einsum("ni,nij->nj", beta, cols[f])
        if shading == "flat":
            fn = _unit(np.cross(pw[faces[:, 1]] - pw[faces[:, 0]], pw[faces[:, 2]] - pw[faces[:, 0]]))
            centroid = pw[faces].mean(axis=1)
            ftint = None if cols is None else cols[faces].mean(axis=1)
            col = illuminate(inst.material, centroid, fn, camera, scene.lights, scene.ambient_light, ftint)
            hdr[mask] = col[tri[mask]]
            normal[mask] = fn[tri[mask]]
        elif shading == "gouraud":
            vcol = illuminate(inst.material, pw, nw, camera, scene.lights, scene.ambient_light, cols)
            hdr[mask] = np.einsum("ni,nij->nj", beta, vcol[f])
            normal[mask] = _unit(np.einsum("ni,nij->nj", beta, nw[f]))
        else:
            if shading == "phong":
                n = _unit(np.einsum("ni,nij->nj", beta, nw[f]))
            else:
                n = quadratic_normal(beta, pw[f], nw[f])
            hdr[mask] = illuminate(inst.material, p, n, camera, scene.lights, scene.ambient_light, tint)
            normal[mask] = n
        position[mask] = p
    return Frame(hdr, depth, normal, position, tri, ins, edge, gap)
