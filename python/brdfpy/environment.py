""":class:`Environment`: light arriving from every direction, for ``Scene(environment=...)``.

An environment is an equirectangular (latitude–longitude) radiance map in linear RGB, row 0 at the zenith
(+y), the middle column straight ahead along −z; it lights every object of the scene and is shown as the
background. Two shading modes (``Scene.render(env_mode=...)``):

* ``"fast"`` (default): no noise, interactive. Diffuse lobes see the order-2 spherical-harmonic irradiance
  (Ramamoorthi & Hanrahan, *An Efficient Representation for Irradiance Environment Maps*, SIGGRAPH 2001),
  glossy lobes the map prefiltered by roughness (the split-sum approximation of Karis, *Real Shading in
  Unreal Engine 4*, SIGGRAPH 2013), both scaled by the material's own directional albedo, so a uniform
  environment is reproduced exactly. No visibility: ``ao=True`` darkens it by the ambient obscurance.
* ``"monte_carlo"``: converges to the rendering equation's reflected radiance with visibility, by multiple
  importance sampling (Veach & Guibas 1995) of the material's sampler and the map's luminance;
  ``env_samples`` iterations (one sample of each strategy) per shaded point, ``env_seed`` for the random
  numbers (the same image at any thread count).
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import as_vectors
from brdfpy._paths import as_path
from brdfpy.lights import color3

__all__ = ["Environment"]


def _number(name: str, x: Any) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name}: expected a number, got {type(x).__name__}")
    return float(x)


class Environment:
    """Radiance arriving from every direction: an equirectangular map, turned about +y and scaled.

    Parameters
    ----------
    image : array_like (H, W, 3)
        Linear RGB radiance, row 0 at the zenith (+y), column ``W/2`` toward −z, ``+x`` at ``3W/4``
        (``u = ½ + atan2(x, −z)/2π``, ``t = acos(y)/π``). Finite and ≥ 0 (checked). For a file, use
        :meth:`load` (``.hdr``, ``.exr``).
    rotation : float
        Degrees about +y: the map's −z direction is seen toward the camera-space direction turned by
        ``rotation`` (counter-clockwise seen from above).
    intensity : float
        Radiance scale, ≥ 0.

    Examples
    --------
    >>> env = brdfpy.Environment.sky()               # a procedural sky, no file needed
    >>> scene = brdfpy.Scene(environment=env)
    >>> scene.add(brdfpy.icosphere(5), brdfpy.model("cook_torrance", roughness=0.2, metal="cu"))
    >>> img = scene.render(brdfpy.Camera.perspective((0, 0, 3)), 640, 480, tonemap="aces")
    """

    __slots__ = ("_e",)

    def __init__(
        self, image: ArrayLike | _brdfpy.RasterEnvironment, *, rotation: float = 0.0, intensity: float = 1.0
    ) -> None:
        if isinstance(image, _brdfpy.RasterEnvironment):
            base = image
        else:
            try:
                a = np.ascontiguousarray(image, dtype=np.float32)
            except (TypeError, ValueError) as e:
                raise TypeError(
                    f"image: expected an (H, W, 3) array of radiance, got {type(image).__name__}"
                ) from e
            if a.ndim != 3:
                raise ValueError(f"image: must have shape (height, width, 3), got shape {a.shape}")
            base = _brdfpy.RasterEnvironment.from_array(a)
        self._e = base.with_(math.radians(_number("rotation", rotation)), _number("intensity", intensity))

    @classmethod
    def _wrap(cls, e: Any, rotation: float, intensity: float) -> Environment:
        return cls(e, rotation=rotation, intensity=intensity)

    @classmethod
    def load(
        cls, path: str | os.PathLike[str], *, rotation: float = 0.0, intensity: float = 1.0
    ) -> Environment:
        """An environment from a Radiance ``.hdr`` (RGBE) or OpenEXR ``.exr`` file (linear RGB; alpha
        dropped), decoded in Rust by the ``image`` crate's decoders (image-rs). A missing, corrupt or
        truncated file raises ``BrdfError`` (a ``ValueError``) naming the file and the problem."""
        return cls._wrap(_brdfpy.RasterEnvironment.load(as_path("path", path)), rotation, intensity)

    @classmethod
    def uniform(cls, radiance: Any = 1.0, *, intensity: float = 1.0) -> Environment:
        """The same ``radiance`` (linear RGB) from every direction: the white furnace, or an ambient sky
        that the fast and Monte Carlo modes light through each material's own reflectance."""
        return cls._wrap(_brdfpy.RasterEnvironment.uniform(color3("radiance", radiance)), 0.0, intensity)

    @classmethod
    def sky(
        cls,
        zenith: Any = (0.35, 0.55, 1.0),
        horizon: Any = (1.0, 0.97, 0.92),
        ground: Any = (0.18, 0.16, 0.14),
        *,
        rotation: float = 0.0,
        intensity: float = 1.0,
    ) -> Environment:
        """A procedural sky over a ground (512 × 256 texels): ``horizon`` blending into ``zenith`` as
        ``√sin(elevation)`` grows, ``ground`` below the horizon (blended over its 3°). Linear RGB."""
        e = _brdfpy.RasterEnvironment.sky(
            color3("zenith", zenith), color3("horizon", horizon), color3("ground", ground)
        )
        return cls._wrap(e, rotation, intensity)

    @classmethod
    def studio(
        cls, *, top: float = 1.0, horizon: float = 0.45, floor: float = 0.06, intensity: float = 1.0
    ) -> Environment:
        """A grey studio gradient: bright above, ``horizon`` at eye level, a dark ``floor``."""
        return cls.sky(top, horizon, floor, intensity=intensity)

    @property
    def rotation(self) -> float:
        """Rotation about +y in degrees."""
        return math.degrees(self._e.rotation)

    @property
    def intensity(self) -> float:
        """Radiance scale."""
        return float(self._e.intensity)

    @property
    def shape(self) -> tuple[int, int]:
        """``(height, width)`` of the map in texels."""
        h, w = self._e.shape
        return (int(h), int(w))

    @property
    def image(self) -> NDArray[np.float32]:
        """The map's texels, float32 (H, W, 3), without rotation or intensity."""
        return self._e.image()

    def rotated(self, degrees: float) -> Environment:
        """The same map turned by ``degrees`` about +y (in place of the current rotation)."""
        return Environment(self._e, rotation=degrees, intensity=self.intensity)

    def scaled(self, intensity: float) -> Environment:
        """The same map with radiance scale ``intensity`` (in place of the current one)."""
        return Environment(self._e, rotation=self.rotation, intensity=intensity)

    def radiance(self, directions: ArrayLike) -> NDArray[np.float32]:
        """Radiance arriving from each world direction (``(N, 3)`` or ``(3,)``; normalised here), float32
        with the same leading shape and 3 channels."""
        d = as_vectors("directions", directions)
        if d.shape[-1:] != (3,):
            raise ValueError(f"directions: expected shape (..., 3), got {d.shape}")
        out = self._e.radiance(np.ascontiguousarray(d.reshape(-1, 3)))
        return out.reshape(d.shape)

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (self.image, self.rotation, self.intensity))

    def __repr__(self) -> str:
        h, w = self.shape
        return f"<brdfpy.Environment {w}×{h}, rotation {self.rotation:g}°, intensity {self.intensity:g}>"


def _rebuild(image: NDArray[np.float32], rotation: float, intensity: float) -> Environment:
    return Environment(image, rotation=rotation, intensity=intensity)
