""":class:`Image`: a rendered frame with its buffers as NumPy arrays, saved through Pillow."""

from __future__ import annotations

import io
import os
from typing import Any, Union

import numpy as np
from numpy.typing import NDArray

from brdfpy import _brdfpy

__all__ = ["Image"]

PathLike = Union[str, "os.PathLike[str]"]


class Image:
    """The result of :meth:`brdfpy.Scene.render`: color, depth, normal and triangle-id buffers.

    Every buffer is ``height × width`` with row 0 at the **top** of the image. Arrays are computed on first
    access, cached and read-only (copy them to edit).

    Attributes
    ----------
    rgb : numpy.ndarray of uint8, (H, W, 3)
        The displayable image: HDR color × 2^exposure → tone map → sRGB → 8 bits, with the render's
        ``tonemap`` and ``exposure``.
    hdr : numpy.ndarray of float32, (H, W, 3)
        Linear RGB radiance before exposure and tone mapping (the background color where nothing was drawn).
    depth : numpy.ndarray of float32, (H, W)
        Window depth in [0, 1] (OpenGL's default depth range; nonlinear in distance under perspective);
        1 where nothing was drawn.
    normal : numpy.ndarray of float32, (H, W, 3)
        Unit world-space shading normal; zero where nothing was drawn.
    triangle_id : numpy.ndarray of int64, (H, W)
        Index of the visible face, counting the faces of all scene instances in the order they were added;
        −1 where nothing was drawn.
    mask : numpy.ndarray of bool, (H, W)
        Where some triangle was drawn.
    """

    __slots__ = ("_cache", "_f")

    def __init__(self, frame: _brdfpy.RasterFrame) -> None:
        if not isinstance(frame, _brdfpy.RasterFrame):
            raise TypeError(f"frame: expected a rendered frame, got {type(frame).__name__}")
        self._f = frame
        self._cache: dict[str, NDArray[Any]] = {}

    def _get(self, name: str) -> NDArray[Any]:
        a = self._cache.get(name)
        if a is None:
            a = getattr(self._f, name if name != "rgb" else "rgb8")()
            a.flags.writeable = False
            self._cache[name] = a
        return a

    @property
    def width(self) -> int:
        """Width in pixels."""
        return self._f.width

    @property
    def height(self) -> int:
        """Height in pixels."""
        return self._f.height

    @property
    def shape(self) -> tuple[int, int]:
        """``(height, width)``."""
        return (self._f.height, self._f.width)

    @property
    def rgb(self) -> NDArray[np.uint8]:
        return self._get("rgb")

    @property
    def hdr(self) -> NDArray[np.float32]:
        return self._get("hdr")

    @property
    def depth(self) -> NDArray[np.float32]:
        return self._get("depth")

    @property
    def normal(self) -> NDArray[np.float32]:
        return self._get("normal")

    @property
    def triangle_id(self) -> NDArray[np.int64]:
        return self._get("triangle_id")

    @property
    def mask(self) -> NDArray[np.bool_]:
        return self.triangle_id >= 0

    @property
    def covered_pixels(self) -> int:
        """Number of pixels some triangle covers."""
        return self._f.covered_pixels()

    def tonemapped(
        self, tonemap: str = "clamp", exposure: float = 0.0, *, white: float | None = None
    ) -> NDArray[np.uint8]:
        """The 8-bit sRGB image with another tone map or exposure than the render's (no re-render):
        ``tonemap`` is one of ``"clamp"``, ``"reinhard"``, ``"reinhard_extended"`` (with ``white``),
        ``"aces"``;
        ``exposure`` in stops."""
        return self._f.rgb8(tonemap, float(exposure), white)

    def to_pil(self) -> Any:
        """The image as a ``PIL.Image.Image`` (RGB, 8 bits)."""
        from PIL import Image as PILImage

        return PILImage.fromarray(np.ascontiguousarray(self.rgb))

    def save(self, path: PathLike, format: str | None = None, **pillow_options: Any) -> None:
        """Write :attr:`rgb` to ``path`` through Pillow; the format follows the extension (PNG, JPEG, ...)
        unless ``format`` is given. Extra keyword arguments go to ``PIL.Image.Image.save``."""
        self.to_pil().save(os.fspath(path), format=format, **pillow_options)

    def _repr_png_(self) -> bytes:
        buf = io.BytesIO()
        self.to_pil().save(buf, format="PNG")
        return buf.getvalue()

    def __repr__(self) -> str:
        return f"<brdfpy.Image {self.width}×{self.height}, {self.covered_pixels} pixels covered>"
