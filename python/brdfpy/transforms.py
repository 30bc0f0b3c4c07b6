"""4×4 transform matrices for placing meshes in a scene (column vectors: ``p' = M @ p``; compose with ``@``,
the rightmost applies first). Angles in degrees.

>>> from brdfpy.transforms import translate, rotate, scale
>>> m = translate(0, 1, 0) @ rotate((0, 1, 0), 90) @ scale(0.5)
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from brdfpy._arrays import _as_numeric
from brdfpy.camera import vec3

__all__ = ["UP_AXES", "identity", "rotate", "scale", "translate", "up_to_y"]

#: The up axes :func:`up_to_y` accepts.
UP_AXES: tuple[str, ...] = ("y", "-y", "z", "-z", "x", "-x")

M4 = NDArray[np.float64]


def identity() -> M4:
    """The 4×4 identity."""
    return np.eye(4)


def translate(x: Any, y: float | None = None, z: float | None = None) -> M4:
    """Translation by ``(x, y, z)`` (or by a sequence of three numbers given as ``x``)."""
    t = vec3("offset", x if y is None and z is None else (x, y, z))
    m = np.eye(4)
    m[:3, 3] = t
    return m


def scale(sx: Any, sy: float | None = None, sz: float | None = None) -> M4:
    """Scaling by ``sx`` on every axis, by the three factors of a sequence ``sx``, or by ``(sx, sy, sz)``;
    factors must be finite and non-zero."""
    if sy is None and sz is None:
        a = _as_numeric("sx", sx)  # (np.ndim would fail on a ragged list with a message naming nothing)
        s = (float(a),) * 3 if a.ndim == 0 else vec3("sx", a)
        name = "sx"
    else:
        s = vec3("(sx, sy, sz)", (sx, sy, sz))
        name = "(sx, sy, sz)"
    if not all(math.isfinite(v) and v != 0 for v in s):
        raise ValueError(f"{name}: scale factors must be finite and non-zero, got {list(s)}")
    return np.diag([s[0], s[1], s[2], 1.0])


def rotate(axis: Any, degrees: float) -> M4:
    """Rotation by ``degrees`` counter-clockwise about ``axis`` (right-hand rule; Rodrigues' formula)."""
    a = np.array(vec3("axis", axis))
    n = float(np.linalg.norm(a))
    if not n > 0:
        raise ValueError("axis: must not be zero")
    x, y, z = a / n
    if isinstance(degrees, bool) or not isinstance(degrees, (int, float, np.integer, np.floating)):
        raise TypeError(f"degrees: expected a number, got {type(degrees).__name__}")
    if not math.isfinite(degrees):
        raise ValueError(f"degrees: must be finite, got {degrees}")
    t = math.radians(float(degrees))
    c, s, k = math.cos(t), math.sin(t), 1 - math.cos(t)
    m = np.eye(4)
    m[:3, :3] = [
        [c + x * x * k, x * y * k - z * s, x * z * k + y * s],
        [y * x * k + z * s, c + y * y * k, y * z * k - x * s],
        [z * x * k - y * s, z * y * k + x * s, c + z * z * k],
    ]
    return m


# Proper rotations (det +1: windings and the outside are kept), one per up axis. For z-up files (CAD,
# 3D printing, Blender) the front faces -y, and the rotation about x that lifts +z to +y also turns -y to
# +z, the front of a y-up asset (glTF 2.0 §3.4: "+Y is up, the front of a glTF asset faces +Z").
_UP_TO_Y: dict[str, list[list[float]]] = {
    "y": [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
    "-y": [[-1, 0, 0], [0, -1, 0], [0, 0, 1]],  # 180° about z: the front (+z) stays
    "z": [[1, 0, 0], [0, 0, 1], [0, -1, 0]],  # -90° about x: (x, y, z) -> (x, z, -y)
    "-z": [[1, 0, 0], [0, 0, -1], [0, 1, 0]],  # +90° about x: (x, y, z) -> (x, -z, y)
    "x": [[0, -1, 0], [1, 0, 0], [0, 0, 1]],  # +90° about z: (x, y, z) -> (-y, x, z)
    "-x": [[0, 1, 0], [-1, 0, 0], [0, 0, 1]],  # -90° about z: (x, y, z) -> (y, -x, z)
}


def up_to_y(up: str) -> M4:
    """The rotation that stands up a mesh whose up axis is ``up`` (``"x"``, ``"-x"``, ``"y"``, ``"-y"``,
    ``"z"``, ``"-z"``) in brdfpy's +y-up world; the identity for ``"y"``.

    For ``"z"`` (CAD, 3D printing and Blender files, whose front faces −y) it is −90° about x,
    ``(x, y, z) → (x, z, −y)``, which also turns that front to +z, where the default cameras look from.
    Every one is a proper rotation (determinant +1), so the winding and the outside are kept.

    >>> up_to_y("z") @ [0, 0, 1, 1]
    array([0., 1., 0., 1.])
    """
    if not isinstance(up, str):
        raise TypeError(f"up: expected one of {', '.join(UP_AXES)}, got {type(up).__name__}")
    key = up.strip().lower().lstrip("+")
    if key not in _UP_TO_Y:
        raise ValueError(f"up: expected one of {', '.join(UP_AXES)}, got {up!r}")
    m = np.eye(4)
    m[:3, :3] = _UP_TO_Y[key]
    return m
