""":class:`Image`: a rendered frame with its buffers as NumPy arrays, saved through Pillow."""

from __future__ import annotations

import io
import os
from typing import Any, Union

import numpy as np
from numpy.typing import NDArray

from brdfpy import _brdfpy
from brdfpy._paths import as_path

__all__ = ["Image"]

PathLike = Union[str, "os.PathLike[str]"]


class Image:
    """The result of :meth:`brdfpy.Scene.render`: color, depth, normal and triangle-id buffers.

    Every buffer is ``height × width`` with row 0 at the **top** of the image. Arrays are computed on first
    access, cached and read-only (copy them to edit). An image holds the buffers its render asked for
    (:attr:`outputs`; ``Scene.render(outputs=...)``, by default ``rgb`` and ``depth``); reading another one
    raises ``BrdfError`` naming it.

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
        Where some triangle was drawn (from ``triangle_id``, or else ``depth``: drawn exactly where the
        depth is below 1).
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
        if "triangle_id" in self.outputs or "depth" not in self.outputs:
            return self.triangle_id >= 0
        return self.depth < 1.0

    @property
    def outputs(self) -> tuple[str, ...]:
        """The buffers this image holds: some of ``"rgb"``, ``"hdr"``, ``"depth"``, ``"normal"``,
        ``"triangle_id"``. :attr:`rgb` is available whenever ``"rgb"`` or ``"hdr"`` is."""
        return tuple(self._f.outputs)

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
        ``exposure`` in stops. Needs the ``"hdr"`` output (unless tone map and exposure are the render's)."""
        if not isinstance(tonemap, str):
            raise TypeError(f"tonemap: expected an operator name (str), got {type(tonemap).__name__}")
        if isinstance(exposure, bool) or not isinstance(exposure, (int, float, np.integer, np.floating)):
            raise TypeError(f"exposure: expected a number, got {type(exposure).__name__}")
        if white is not None and (isinstance(white, bool) or not isinstance(white, (int, float, np.number))):
            raise TypeError(f"white: expected a number, got {type(white).__name__}")
        return self._f.rgb8(tonemap, float(exposure), white)

    def to_pil(self) -> Any:
        """The image as a ``PIL.Image.Image`` (RGB, 8 bits)."""
        from PIL import Image as PILImage

        return PILImage.fromarray(np.ascontiguousarray(self.rgb))

    def save(self, path: PathLike, format: str | None = None, **pillow_options: Any) -> None:
        """Write :attr:`rgb` to ``path`` through Pillow; the format follows the extension (PNG, JPEG, ...)
        unless ``format`` is given. Extra keyword arguments go to ``PIL.Image.Image.save``.

        A ``.hdr`` path (or ``format="HDR"``) writes the linear :attr:`hdr` radiance instead, as a Radiance
        RGBE file (Ward 1991; shared 8-bit exponent, about 1 % precision), and an ``.exr`` path (or
        ``format="EXR"``) as an OpenEXR file of 32-bit floats (exact); both need the ``"hdr"`` output and are
        what HDR viewers, compositors and :meth:`brdfpy.Environment.load` read."""
        from PIL import Image as PILImage

        p = as_path("path", path)
        ext = os.path.splitext(p)[1].lower()
        fmt = format.upper() if isinstance(format, str) else None
        hdr_format = {"HDR": "hdr", "RADIANCE": "hdr", "EXR": "exr", "OPENEXR": "exr"}.get(fmt or "")
        if fmt is None and ext in (".hdr", ".exr"):
            hdr_format = ext[1:]
        if hdr_format is not None:
            if pillow_options:
                raise TypeError(f"save: .{hdr_format} takes no Pillow options, got {sorted(pillow_options)}")
            data = self._f.hdr_file() if hdr_format == "hdr" else self._f.exr_file()
            with open(p, "wb") as f:
                f.write(data)
            return
        PILImage.init()
        if format is not None:
            if not isinstance(format, str):
                raise TypeError(
                    f"format: expected an image format name such as 'PNG', got {type(format).__name__}"
                )
            if format.upper() not in PILImage.SAVE:
                raise ValueError(
                    f"format: Pillow cannot write {format!r}; it writes {', '.join(sorted(PILImage.SAVE))}"
                )
        else:
            ext = os.path.splitext(p)[1].lower()
            if PILImage.registered_extensions().get(ext) not in PILImage.SAVE:
                raise ValueError(
                    f"path: Pillow cannot write files with the extension {ext!r} ({p!r}): "
                    "use .png, .jpg, ... or give format="
                )
        self.to_pil().save(p, format=format, **pillow_options)

    def _repr_png_(self) -> bytes:
        buf = io.BytesIO()
        self.to_pil().save(buf, format="PNG")
        return buf.getvalue()

    def __reduce__(self) -> tuple[Any, ...]:
        # Every buffer of the frame (not the cache of arrays already read), rebuilt with the same bits.
        return (_rebuild_image, (_brdfpy._frame_state(self._f),))

    def __repr__(self) -> str:
        if {"depth", "triangle_id"} & set(self.outputs):
            return f"<brdfpy.Image {self.width}×{self.height}, {self.covered_pixels} pixels covered>"
        return f"<brdfpy.Image {self.width}×{self.height}, outputs {', '.join(self.outputs)}>"


def _rebuild_image(state: tuple[Any, ...]) -> Image:
    # Buffers from the network may be unaligned: the compiled module reads aligned arrays only.
    w, h, hdr, depth, normal, ids, rgb8, tonemap, white, exposure = state
    hdr, depth, normal, ids, rgb8 = (
        np.require(a, a.dtype, ["C", "A"]) for a in (hdr, depth, normal, ids, rgb8)
    )
    return Image(_brdfpy._frame_from_state(w, h, hdr, depth, normal, ids, rgb8, tonemap, white, exposure))
