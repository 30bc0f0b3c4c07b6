""":class:`Texture`: an image a material reads at every shaded point — any colour or scalar parameter of
its model (``brdfpy.model("cook_torrance", kd=Texture("wood.png"), roughness=Texture(a).channel(1))``), or a
normal, occlusion or emission map (``Scene.add(mesh, model, normal_map=..., occlusion_map=...,
emission=...)``).

**Texture coordinates** follow glTF 2.0: ``(0, 0)`` is the top-left corner of the image, ``(1, 1)`` its
bottom-right corner, ``v`` grows downward, and row 0 of an array is the top row of the image. Texel ``(i,
j)`` (column ``i``, row ``j``) has its centre at ``((i + 0.5)/W, (j + 0.5)/H)``. A mesh carries them as
``Mesh(..., uvs=...)``.

**Colour.** Texels are linear. 8-bit data (a NumPy ``uint8`` array or an 8-bit image file) is sRGB-decoded
by default (as glTF's base-colour and emissive textures are); ``colorspace="linear"`` reads ``x/255``
instead (glTF's metallic-roughness, normal and occlusion textures). 16-bit data is ``x/65535`` and float
data is taken as it is, both linear unless ``colorspace="srgb"``. Alpha is always linear. The decoding and
every check (finite, non-negative, size) happen in the compiled core.

**Filtering.** ``"nearest"`` (the texel under the point), ``"bilinear"`` (the four nearest texel centres)
or ``"trilinear"`` (default: bilinear in the two mip levels around the level of detail
``λ = log2 max(|∂(uW, vH)/∂x|, |∂(uW, vH)/∂y|)``, OpenGL 4.6 eq. 8.7, from the screen-space derivatives of
the perspective-correct texture coordinates; the mip chain is box-filtered). **Wrap** outside ``[0, 1)``:
``"repeat"``, ``"clamp"`` (to the edge texel) or ``"mirror"`` (mirrored repeat), glTF's three modes.
"""

from __future__ import annotations

import os
from typing import Any, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import _as_numeric, _to_f32

__all__ = ["FILTERS", "WRAPS", "Texture", "TextureChannel"]

#: Wrap modes (glTF's REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT).
WRAPS = ("repeat", "clamp", "mirror")
#: Filters.
FILTERS = ("nearest", "bilinear", "trilinear")


def _image_array(path: str | os.PathLike[str]) -> NDArray[Any]:
    """The texels of an image file through Pillow: uint8 (H, W[, 3|4]), uint16 (H, W) or float32 (H, W)."""
    from PIL import Image as PILImage

    with PILImage.open(path) as im:
        im.load()
        mode = im.mode
        if mode in ("I;16", "I;16B", "I;16L"):
            return np.asarray(im, dtype=np.uint16)
        if mode == "F":
            return np.asarray(im, dtype=np.float32)
        if mode == "L":
            return np.asarray(im, dtype=np.uint8)
        if mode in ("RGB", "RGBA"):
            return np.asarray(im, dtype=np.uint8)
        has_alpha = mode in ("LA", "PA", "La") or (mode == "P" and "transparency" in im.info)
        return np.asarray(im.convert("RGBA" if has_alpha else "RGB"), dtype=np.uint8)


class Texture:
    """An image of linear texels (1, 3 or 4 channels) with its mip chain, wrap mode and filter.

    Parameters
    ----------
    data_or_path : array_like or str or os.PathLike
        A NumPy array of shape ``(H, W)``, ``(H, W, 3)`` or ``(H, W, 4)`` (row 0 the top of the image) of
        floats (linear; converted to float32), ``uint8`` or ``uint16``; or the path of an image file, read
        with Pillow (8-bit grey, RGB, RGBA and palette images; 16-bit and float grey images).
    wrap : str
        ``"repeat"`` (default), ``"clamp"`` or ``"mirror"`` (see the module docs).
    filter : str
        ``"trilinear"`` (default, mip-mapped), ``"bilinear"`` or ``"nearest"``.
    colorspace : str, optional
        ``"srgb"`` or ``"linear"``: how the values encode linear ones. Default: sRGB for 8-bit data,
        linear for 16-bit and float data.

    Raises
    ------
    ValueError
        Zero size, more than 16384 texels a side or 2^26 in all, a NaN, infinite or negative texel (the
        message gives the texel), a shape with other than 1, 3 or 4 channels, an unknown name.
    TypeError
        Data of another type (e.g. int64 or bool arrays: say what the integers mean by converting them).
    """

    __slots__ = ("_t",)

    def __init__(
        self,
        data_or_path: ArrayLike | str | os.PathLike[str],
        *,
        wrap: str = "repeat",
        filter: str = "trilinear",
        colorspace: str | None = None,
    ) -> None:
        for name, v, known in (("wrap", wrap, WRAPS), ("filter", filter, FILTERS)):
            if not isinstance(v, str):
                raise TypeError(f"{name}: expected one of {', '.join(known)}, got {type(v).__name__}")
        if colorspace is not None and not isinstance(colorspace, str):
            raise TypeError(f"colorspace: expected 'srgb', 'linear' or None, got {type(colorspace).__name__}")
        if isinstance(data_or_path, (str, os.PathLike)):
            a = _image_array(data_or_path)
        else:
            a = np.asarray(data_or_path)
            if a.dtype.kind == "f":
                a = a.astype(np.float32, copy=False)
            elif a.dtype not in (np.uint8, np.uint16):
                raise TypeError(
                    f"data_or_path: expected an array of floats, uint8 or uint16, got dtype {a.dtype}"
                )
        self._t = _brdfpy.RasterTexture(np.ascontiguousarray(a), wrap, filter, colorspace)

    @property
    def width(self) -> int:
        """Width in texels."""
        return int(self._t.width)

    @property
    def height(self) -> int:
        """Height in texels."""
        return int(self._t.height)

    @property
    def channels(self) -> int:
        """Values per texel: 1, 3 or 4."""
        return int(self._t.channels)

    @property
    def wrap(self) -> str:
        """The wrap mode."""
        return str(self._t.wrap)

    @property
    def filter(self) -> str:
        """The filter."""
        return str(self._t.filter)

    @property
    def mean(self) -> tuple[float, float, float, float]:
        """The mean of each channel over the image as RGBA (one channel reads as grey, alpha 1 without
        one)."""
        m = self._t.mean
        return (float(m[0]), float(m[1]), float(m[2]), float(m[3]))

    def levels(self) -> list[NDArray[np.float32]]:
        """The mip chain, float32 ``(h, w, channels)`` each, level 0 (the image, linear) first; only level 0
        unless the filter is trilinear. Each level halves the last (``max(1, ⌊n/2⌋)``), every texel the area
        average of the texels under it."""
        return list(self._t.levels())

    def sample(
        self, uv: ArrayLike, duv_dx: ArrayLike | None = None, duv_dy: ArrayLike | None = None
    ) -> NDArray[np.float32]:
        """The filtered linear RGBA at texture coordinates ``uv`` (shape ``(N, 2)``), as the renderer reads
        it for a point whose coordinates change by ``duv_dx`` per screen column and ``duv_dy`` per row
        (``(N, 2)`` each, zero by default: the base level); float32 ``(N, 4)``."""
        u = _uv_rows("uv", uv)
        zero = np.zeros_like(u)
        dx = zero if duv_dx is None else _uv_rows("duv_dx", duv_dx)
        dy = zero if duv_dy is None else _uv_rows("duv_dy", duv_dy)
        out: NDArray[np.float32] = self._t.sample(u, dx, dy)
        return out

    def channel(self, k: int) -> TextureChannel:
        """This texture's channel ``k`` (0 red, 1 green, 2 blue, 3 alpha), for a scalar parameter:
        ``roughness=tex.channel(1)`` reads glTF's roughness (G of a metallic-roughness texture)."""
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
            raise TypeError(f"channel: expected an integer 0-3, got {type(k).__name__}")
        if not 0 <= int(k) < self.channels:
            raise ValueError(
                f"channel: must be in 0..{self.channels - 1} for a {self.channels}-channel texture, got {k}"
            )
        return TextureChannel(self, int(k))

    def __repr__(self) -> str:
        return str(self._t.__repr__())


def _uv_rows(name: str, x: ArrayLike) -> NDArray[np.float32]:
    """``x`` as contiguous float32 rows of two texture coordinates, refused naming ``name`` otherwise."""
    a = _to_f32(name, _as_numeric(name, x))
    if a.ndim == 0 or a.shape[-1] != 2:
        raise ValueError(f"{name}: expected texture coordinates of shape (N, 2), got shape {a.shape}")
    return np.ascontiguousarray(a.reshape(-1, 2))


class TextureChannel:
    """One channel of a :class:`Texture` (from :meth:`Texture.channel`), read by a scalar parameter or an
    occlusion map."""

    __slots__ = ("index", "texture")

    def __init__(self, texture: Texture, index: int) -> None:
        self.texture = texture
        self.index = index

    def __repr__(self) -> str:
        return f"{self.texture!r}.channel({self.index})"


#: What a texture binding accepts.
TextureLike = Union[Texture, TextureChannel]


def texture_read(name: str, t: Any) -> tuple[Any, int | None]:
    """``(compiled texture, channel or None)`` of a :class:`Texture` or :class:`TextureChannel`."""
    if isinstance(t, TextureChannel):
        return (t.texture._t, t.index)
    if isinstance(t, Texture):
        return (t._t, None)
    raise TypeError(f"{name}: expected a brdfpy.Texture (or tex.channel(k)), got {type(t).__name__}")
