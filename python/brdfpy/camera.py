"""Look-at cameras with OpenGL conventions: right-handed world, +y up, the camera looks down its −z axis,
``p_clip = P · V · p_world``, NDC z in [−1, 1]; image row 0 is the top. Angles are in **degrees** here."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import as_f64, as_float

__all__ = ["Camera", "vec3"]


def vec3(name: str, x: Any) -> tuple[float, float, float]:
    """Three finite numbers from a sequence or array of 3 (errors name the argument; complex, bool and
    str input are refused, not cast)."""
    if isinstance(x, (str, bytes)) or x is None:
        raise TypeError(f"{name}: expected three numbers, got {type(x).__name__}")
    a = as_f64(name, x)
    if a.shape != (3,):
        raise ValueError(f"{name}: expected three numbers, got shape {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"{name}: must be finite, got {a.tolist()}")
    return (float(a[0]), float(a[1]), float(a[2]))


#: The widest aspect ratio of an image the renderer makes (its largest side × 1): the limit of ``aspect``.
_MAX_ASPECT: int = _brdfpy.raster_limits()[0]


def _number(name: str, x: Any) -> float:
    return as_float(name, x)


class Camera:
    """A look-at camera, perspective or orthographic.

    ``Camera(eye, target, up, fovy, near, far)`` is :meth:`Camera.perspective`. The image's aspect ratio
    comes from the render size, so one camera serves any image size. Immutable.

    The view matrix is the classic lookAt: ``z = normalize(eye − target)``, ``x = normalize(up × z)``,
    ``y = z × x``; the perspective projection is ``gluPerspective`` (vertical field of view), the
    orthographic one ``glOrtho`` of a volume ``height`` tall.
    """

    __slots__ = ("_c",)

    _c: _brdfpy.RasterCamera

    def __init__(
        self,
        eye: ArrayLike = (0.0, 0.0, 3.0),
        target: ArrayLike = (0.0, 0.0, 0.0),
        up: ArrayLike = (0.0, 1.0, 0.0),
        fovy: float = 45.0,
        near: float = 0.1,
        far: float = 100.0,
    ) -> None:
        self._c = Camera.perspective(eye, target, up, fovy, near, far)._c

    @classmethod
    def perspective(
        cls,
        eye: ArrayLike,
        target: ArrayLike = (0.0, 0.0, 0.0),
        up: ArrayLike = (0.0, 1.0, 0.0),
        fovy: float = 45.0,
        near: float = 0.1,
        far: float = 100.0,
    ) -> Camera:
        """A perspective camera at ``eye`` looking at ``target``.

        Parameters
        ----------
        eye, target : three numbers
            Camera position and the point it looks at (must differ).
        up : three numbers
            Which way is up on screen; need not be unit or perpendicular to the view, must not be parallel.
        fovy : float
            Full **vertical** field of view in **degrees**, in (0, 180). 45 by default.
        near, far : float
            Clip distances, ``0 < near < far``. Geometry nearer than ``near`` is clipped, not dropped.

        Raises
        ------
        ValueError
            ``eye == target``, ``up`` parallel to the view direction, angles or distances out of range
            (the message names the argument).

        Examples
        --------
        >>> cam = brdfpy.Camera.perspective(eye=(0, 0, 3), target=(0, 0, 0), fovy=45)
        """
        f = _number("fovy", fovy)
        if not (0.0 < f < 180.0):
            raise ValueError(f"fovy: must lie in (0, 180) degrees, got {f}")
        raw = _brdfpy.RasterCamera.perspective(
            vec3("eye", eye),
            vec3("target", target),
            vec3("up", up),
            math.radians(f),
            _number("near", near),
            _number("far", far),
        )
        return cls._wrap(raw)

    @classmethod
    def orthographic(
        cls,
        eye: ArrayLike,
        target: ArrayLike = (0.0, 0.0, 0.0),
        up: ArrayLike = (0.0, 1.0, 0.0),
        height: float = 2.0,
        near: float = 0.1,
        far: float = 100.0,
    ) -> Camera:
        """A parallel-projection camera: the view volume is ``height`` world units tall (its width follows
        the image's aspect ratio), centred on the line from ``eye`` to ``target``; the viewer is at
        infinity (the view vector is the same everywhere)."""
        raw = _brdfpy.RasterCamera.orthographic(
            vec3("eye", eye),
            vec3("target", target),
            vec3("up", up),
            _number("height", height),
            _number("near", near),
            _number("far", far),
        )
        return cls._wrap(raw)

    @classmethod
    def framing(
        cls,
        center: ArrayLike,
        radius: float,
        direction: ArrayLike = (0.0, 0.0, 1.0),
        *,
        up: ArrayLike = (0.0, 1.0, 0.0),
        fovy: float = 45.0,
        aspect: float = 1.0,
        margin: float = 1.1,
    ) -> Camera:
        """A perspective camera that shows the sphere (``center``, ``radius``) whole, seen from
        ``direction`` (from the centre toward the eye), on an image of aspect ``aspect`` = width / height,
        with ``margin`` (1.1: 10 % room around it)."""
        r = _number("radius", radius)
        if not (r > 0 and math.isfinite(r)):
            raise ValueError(f"radius: must be finite and > 0, got {r}")
        d = np.array(vec3("direction", direction))
        if not np.linalg.norm(d) > 0:
            raise ValueError("direction: must not be zero")
        d /= np.linalg.norm(d)
        fov = _number("fovy", fovy)
        if not 0 < fov < 180:
            raise ValueError(f"fovy: must lie in (0, 180) degrees, got {fov}")
        a = _number("aspect", aspect)
        if not 1 / _MAX_ASPECT <= a <= _MAX_ASPECT:
            raise ValueError(
                f"aspect: must be a width/height ratio in [1/{_MAX_ASPECT}, {_MAX_ASPECT}], got {a}"
            )
        m = _number("margin", margin)
        if not (m > 0 and math.isfinite(m)):
            raise ValueError(f"margin: must be finite and > 0, got {m}")
        half_v = math.radians(fov) / 2
        half_h = math.atan(math.tan(half_v) * a)
        half = min(half_v, half_h)
        if not math.sin(half) > 0:  # a fovy of 1e-320 degrees rounds its half-angle to 0
            raise ValueError(f"fovy: {fov} degrees is too small to frame anything")
        dist = r * m / math.sin(half)
        if not math.isfinite(dist):
            raise ValueError(f"radius: {r} is too large to frame (the eye would be at distance {dist})")
        c = np.array(vec3("center", center))
        eye = c + d * dist
        return cls.perspective(eye, c, up, fovy, near=max(dist - 2 * r, dist * 1e-3), far=dist + 4 * r)

    @classmethod
    def _wrap(cls, raw: _brdfpy.RasterCamera) -> Camera:
        c = cls.__new__(cls)
        c._c = raw
        return c

    @property
    def kind(self) -> str:
        """``"perspective"`` or ``"orthographic"``."""
        return self._c.kind

    @property
    def eye(self) -> tuple[float, float, float]:
        """Camera position."""
        return tuple(self._c.eye)  # type: ignore[return-value]

    @property
    def target(self) -> tuple[float, float, float]:
        """The point looked at."""
        return tuple(self._c.target)  # type: ignore[return-value]

    @property
    def up(self) -> tuple[float, float, float]:
        """The up hint."""
        return tuple(self._c.up)  # type: ignore[return-value]

    @property
    def fovy(self) -> float | None:
        """Vertical field of view in degrees (``None`` for an orthographic camera)."""
        return math.degrees(self._c.extent) if self.kind == "perspective" else None

    @property
    def height(self) -> float | None:
        """View-volume height (``None`` for a perspective camera)."""
        return self._c.extent if self.kind == "orthographic" else None

    @property
    def near(self) -> float:
        """Near clip distance."""
        return self._c.near

    @property
    def far(self) -> float:
        """Far clip distance."""
        return self._c.far

    def view_matrix(self) -> NDArray[np.float64]:
        """The view matrix ``V`` (4×4, world → camera, column vectors: ``p_cam = V @ p``)."""
        return np.array(self._c.view_matrix(), dtype=np.float64)

    def projection_matrix(self, aspect: float) -> NDArray[np.float64]:
        """The projection matrix ``P`` (4×4, OpenGL clip space) for an image of ``aspect`` = width/height."""
        return np.array(self._c.projection_matrix(_number("aspect", aspect)), dtype=np.float64)

    def __reduce__(self) -> tuple[Any, ...]:
        # The stored float32 fields, not the degrees of the public constructors (whose conversion to
        # radians would not give back the same bits).
        c = self._c
        return (_rebuild_camera, (c.kind, c.eye, c.target, c.up, c.extent, c.near, c.far))

    def __repr__(self) -> str:
        e, t = self.eye, self.target
        eye = ", ".join(f"{x:g}" for x in e)
        tgt = ", ".join(f"{x:g}" for x in t)
        if self.kind == "perspective":
            return f"brdfpy.Camera.perspective(eye=({eye}), target=({tgt}), fovy={self.fovy:g})"
        return f"brdfpy.Camera.orthographic(eye=({eye}), target=({tgt}), height={self.height:g})"


def _rebuild_camera(
    kind: str,
    eye: list[float],
    target: list[float],
    up: list[float],
    extent: float,
    near: float,
    far: float,
) -> Camera:
    make = _brdfpy.RasterCamera.perspective if kind == "perspective" else _brdfpy.RasterCamera.orthographic
    return Camera._wrap(make(_v3(eye), _v3(target), _v3(up), extent, near, far))


def _v3(x: list[float]) -> tuple[float, float, float]:
    return (x[0], x[1], x[2])
