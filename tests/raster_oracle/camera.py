"""Cameras in OpenGL conventions (SCENE.md "Camera"): column vectors, ``p_clip = P V p_world``,
NDC z in [-1, 1], the camera looks down its local -z.

Sources: the gluLookAt and gluPerspective / glOrtho manual pages (matrices written out in SCENE.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]


def _unit(a: F64) -> F64:
    return a / np.linalg.norm(a)


def look_at(eye: ArrayLike, target: ArrayLike, up: ArrayLike = (0.0, 1.0, 0.0)) -> F64:
    """SCENE.md: ``z = normalize(eye - target)``, ``x = normalize(up x z)``, ``y = z x x``; rows 0-2 of
    the view matrix are x, y, z and its translation column is ``-R eye``."""
    eye = np.asarray(eye, dtype=np.float64)
    z = _unit(eye - np.asarray(target, dtype=np.float64))
    x = _unit(np.cross(np.asarray(up, dtype=np.float64), z))
    y = np.cross(z, x)
    v = np.eye(4)
    v[0, :3], v[1, :3], v[2, :3] = x, y, z
    v[:3, 3] = -v[:3, :3] @ eye
    return v


def perspective(fovy_deg: float, aspect: float, near: float, far: float) -> F64:
    """gluPerspective: ``f = 1/tan(fovy/2)``, ``[[f/aspect,0,0,0],[0,f,0,0],[0,0,(F+n)/(n-F),2Fn/(n-F)],
    [0,0,-1,0]]``."""
    f = 1.0 / np.tan(np.deg2rad(fovy_deg) / 2.0)
    n, fa = near, far
    return np.array(
        [
            [f / aspect, 0, 0, 0],
            [0, f, 0, 0],
            [0, 0, (fa + n) / (n - fa), 2 * fa * n / (n - fa)],
            [0, 0, -1, 0],
        ],
        dtype=np.float64,
    )


def orthographic(height: float, aspect: float, near: float, far: float) -> F64:
    """glOrtho with a symmetric view volume ``height`` tall and ``height*aspect`` wide:
    ``diag(2/w, 2/h, -2/(F-n))`` and z offset ``-(F+n)/(F-n)``; w_clip = 1."""
    w = height * aspect
    return np.array(
        [
            [2 / w, 0, 0, 0],
            [0, 2 / height, 0, 0],
            [0, 0, -2 / (far - near), -(far + near) / (far - near)],
            [0, 0, 0, 1],
        ],
        dtype=np.float64,
    )


@dataclass
class Camera:
    """A look-at camera. ``fovy`` in degrees (perspective) or ``height`` (orthographic, world units)."""

    eye: F64
    target: F64
    up: F64
    near: float
    far: float
    fovy: float | None = None
    height: float | None = None

    @classmethod
    def perspective(
        cls,
        eye: ArrayLike,
        target: ArrayLike = (0, 0, 0),
        up: ArrayLike = (0, 1, 0),
        fovy: float = 45.0,
        near: float = 0.1,
        far: float = 100.0,
    ) -> Camera:
        return cls(*(np.asarray(a, dtype=np.float64) for a in (eye, target, up)), near, far, fovy=fovy)

    @classmethod
    def orthographic(
        cls,
        eye: ArrayLike,
        target: ArrayLike = (0, 0, 0),
        up: ArrayLike = (0, 1, 0),
        height: float = 2.0,
        near: float = 0.1,
        far: float = 100.0,
    ) -> Camera:
        return cls(*(np.asarray(a, dtype=np.float64) for a in (eye, target, up)), near, far, height=height)

    @property
    def is_ortho(self) -> bool:
        return self.height is not None

    def view(self) -> F64:
        return look_at(self.eye, self.target, self.up)

    def projection(self, aspect: float) -> F64:
        if self.height is not None:
            return orthographic(self.height, aspect, self.near, self.far)
        assert self.fovy is not None
        return perspective(self.fovy, aspect, self.near, self.far)

    def view_projection(self, aspect: float) -> F64:
        return self.projection(aspect) @ self.view()

    def view_vector(self, p: F64) -> F64:
        """Unit vector from the surface toward the viewer. Perspective: ``normalize(eye - P)`` (SCENE.md
        "Interpolation"). Orthographic: the eye is at infinity, so the constant
        ``normalize(eye - target)``."""
        if self.is_ortho:
            z = _unit(self.eye - self.target)
            return np.broadcast_to(z, p.shape).copy()
        d = self.eye - p
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    def ray(self, width: int, height: int) -> tuple[F64, F64]:
        """Origins and unit directions (H, W, 3) of the rays through the pixel centres (SCENE.md
        "Viewport": column c, row r from the top sample ``x_ndc = 2(c+0.5)/W - 1``,
        ``y_ndc = 1 - 2(r+0.5)/H``), by un-projecting NDC points on the near and far planes."""
        vp = self.view_projection(width / height)
        inv = np.linalg.inv(vp)
        c, r = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
        x = 2 * c / width - 1
        y = 1 - 2 * r / height
        pts = []
        for z in (-1.0, 1.0):
            ndc = np.stack([x, y, np.full_like(x, z), np.ones_like(x)], axis=-1)
            w = ndc @ inv.T
            pts.append(w[..., :3] / w[..., 3:])
        d = pts[1] - pts[0]
        return pts[0], d / np.linalg.norm(d, axis=-1, keepdims=True)

    def unproject(self, ndc_xy: ArrayLike, depth: ArrayLike, aspect: float) -> F64:
        """World points (N, 3) seen at NDC ``(x, y)`` (N, 2) at view-space distance ``depth`` (N,) in
        front of the camera (``near <= depth <= far``): on the segment between the point's near- and
        far-plane images, along which view-space depth is affine."""
        xy = np.asarray(ndc_xy, dtype=np.float64).reshape(-1, 2)
        inv = np.linalg.inv(self.view_projection(aspect))
        ends = []
        for z in (-1.0, 1.0):
            ndc = np.column_stack([xy, np.full(len(xy), z), np.ones(len(xy))])
            w = ndc @ inv.T
            ends.append(w[:, :3] / w[:, 3:])
        u = (np.asarray(depth, dtype=np.float64) - self.near) / (self.far - self.near)
        return ends[0] + u[:, None] * (ends[1] - ends[0])
