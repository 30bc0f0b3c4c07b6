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

import io
import os
from typing import Any, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import _as_numeric, _to_f32

__all__ = ["FILTERS", "WRAPS", "Texture", "TextureChannel", "TextureSource"]

#: Wrap modes (glTF's REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT).
WRAPS = ("repeat", "clamp", "mirror")
#: Filters.
FILTERS = ("nearest", "bilinear", "trilinear")


def _image_array(path: str | os.PathLike[str] | io.BytesIO) -> NDArray[Any]:
    """The texels of an image file (or its encoded bytes) through Pillow: uint8 (H, W[, 3|4]), uint16 (H, W)
    or float32 (H, W)."""
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
    wrap : str or (str, str)
        ``"repeat"`` (default), ``"clamp"`` or ``"mirror"`` (see the module docs); a pair gives the modes
        along ``u`` and ``v`` (glTF's ``wrapS`` and ``wrapT``).
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
        wrap: str | tuple[str, str] = "repeat",
        filter: str = "trilinear",
        colorspace: str | None = None,
    ) -> None:
        wrap_u, wrap_v = _wrap_pair(wrap)
        for name, v, known in (("filter", filter, FILTERS),):
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
        self._t = _brdfpy.RasterTexture(np.ascontiguousarray(a), wrap_u, filter, colorspace, wrap_v)

    @classmethod
    def from_bytes(
        cls,
        data: bytes,
        *,
        wrap: str | tuple[str, str] = "repeat",
        filter: str = "trilinear",
        colorspace: str | None = None,
    ) -> Texture:
        """A texture from an encoded image (PNG, JPEG, ... as Pillow reads them; e.g. a glTF buffer view),
        with the options of :class:`Texture`."""
        if not isinstance(data, (bytes, bytearray, memoryview)):
            raise TypeError(f"data: expected the bytes of an encoded image, got {type(data).__name__}")
        try:
            a = _image_array(io.BytesIO(bytes(data)))
        except Exception as e:  # Pillow raises several types (UnidentifiedImageError, OSError, ...)
            raise ValueError(f"data: not an image Pillow can decode ({e})") from e
        return cls(a, wrap=wrap, filter=filter, colorspace=colorspace)

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
    def wrap(self) -> str | tuple[str, str]:
        """The wrap mode, or the pair ``(u, v)`` when they differ."""
        u, v = str(self._t.wrap), str(self._t.wrap_v)
        return u if u == v else (u, v)

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


def _wrap_pair(wrap: Any) -> tuple[str, str]:
    """``(u, v)`` wrap modes of a name or a pair of names (checked by name in the core)."""
    if isinstance(wrap, str):
        return wrap, wrap
    if isinstance(wrap, (tuple, list)) and len(wrap) == 2 and all(isinstance(w, str) for w in wrap):
        return str(wrap[0]), str(wrap[1])
    raise TypeError(f"wrap: expected one of {', '.join(WRAPS)} or a pair of them, got {wrap!r}")


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


_Read = tuple[Union[Texture, None], Union[int, None], tuple[float, float, float]]

#: The kinds of :class:`TextureSource`, the core's ``ParamSource``.
SOURCE_KINDS = ("texture", "squared", "metallic_diffuse", "metallic_f0")


class TextureSource:
    """A parameter value computed from textures per shaded point, for what one texture read cannot say:
    ``factor ∘ texel`` (:meth:`scaled`), its square (:meth:`squared`: glTF's perceptual roughness → α), and
    glTF 2.0 Appendix B's metallic mixes (:meth:`metallic_diffuse`: ``(1 − metallic)·baseColor``,
    :meth:`metallic_f0`: ``mix(0.04, baseColor, metallic)``). Bind it like a texture:
    ``brdfpy.model("cook_torrance", roughness=TextureSource.squared(mr.channel(1), 0.8))``. Each read is a
    :class:`Texture` (RGB), a :class:`TextureChannel` or a constant (a number or three), times its factor;
    values are clamped into the parameter's range as for any texture."""

    __slots__ = ("kind", "reads")

    def __init__(self, kind: str, reads: list[_Read]) -> None:
        if not isinstance(kind, str) or kind not in SOURCE_KINDS:
            raise ValueError(f"kind: expected one of {', '.join(SOURCE_KINDS)}, got {kind!r}")
        want = 1 if kind in ("texture", "squared") else 2
        if not isinstance(reads, (list, tuple)) or len(reads) != want:
            raise ValueError(
                f"reads: a {kind} source reads {want} (texture, channel, factor) triple(s), got {reads!r}"
            )
        self.kind = kind
        self.reads = [_checked_read(f"reads[{i}]", r) for i, r in enumerate(reads)]

    @classmethod
    def scaled(cls, texture: Texture | TextureChannel, factor: ArrayLike = 1.0) -> TextureSource:
        """``factor ∘ texel`` (a number, or RGB factors for a colour)."""
        return cls("texture", [_read("texture", texture, factor)])

    @classmethod
    def squared(cls, texture: Texture | TextureChannel, factor: ArrayLike = 1.0) -> TextureSource:
        """``(factor ∘ texel)²``: glTF's roughness ``r`` (G of the metallic-roughness texture times
        ``roughnessFactor``) as the microfacet ``α = r²`` of ``cook_torrance``'s ``roughness``."""
        return cls("squared", [_read("texture", texture, factor)])

    @classmethod
    def metallic_diffuse(cls, base_color: Any, metallic: Any) -> TextureSource:
        """``(1 − metallic)·baseColor`` (glTF 2.0 Appendix B's diffuse colour, for ``kd``). ``base_color``:
        a Texture, a :meth:`scaled` one or constant RGB; ``metallic``: a TextureChannel, a :meth:`scaled`
        one or a constant."""
        return cls("metallic_diffuse", [_read_of("base_color", base_color), _read_of("metallic", metallic)])

    @classmethod
    def metallic_f0(cls, base_color: Any, metallic: Any) -> TextureSource:
        """``mix(0.04, baseColor, metallic)`` (glTF 2.0 Appendix B's normal-incidence reflectance, for
        ``f0``); arguments as for :meth:`metallic_diffuse`."""
        return cls("metallic_f0", [_read_of("base_color", base_color), _read_of("metallic", metallic)])

    def mean(self) -> NDArray[np.float64]:
        """The value at the textures' means (RGB; the means, not the mean of the values: exact for the
        linear kinds), what :attr:`TexturedModel.params` shows."""
        m = [_read_mean(r) for r in self.reads]
        if self.kind == "texture":
            return m[0]
        if self.kind == "squared":
            return m[0] * m[0]
        metal = float(np.clip(m[1][0], 0.0, 1.0))
        if self.kind == "metallic_diffuse":
            return m[0] * (1.0 - metal)
        return 0.04 * (1.0 - metal) + m[0] * metal

    def textures(self) -> list[Texture]:
        """The textures this source reads."""
        return [t for t, _, _ in self.reads if t is not None]

    def _args(self) -> tuple[str, list[tuple[Any, int | None, tuple[float, float, float]]]]:
        return self.kind, [(None if t is None else t._t, c, f) for t, c, f in self.reads]

    def __eq__(self, other: object) -> bool:
        return isinstance(other, TextureSource) and (self.kind, self.reads) == (other.kind, other.reads)

    def __hash__(self) -> int:
        return hash((self.kind, tuple((id(t), c, f) for t, c, f in self.reads)))

    def __reduce__(self) -> Any:
        return (TextureSource, (self.kind, self.reads))

    def __repr__(self) -> str:
        def one(r: _Read) -> str:
            t, c, f = r
            if t is None:
                return repr(f)
            base = repr(t) if c is None else f"{t!r}.channel({c})"
            return base if f == (1.0, 1.0, 1.0) else f"{base} * {f}"

        return f"TextureSource.{self.kind}({', '.join(one(r) for r in self.reads)})"


def _checked_read(name: str, r: Any) -> _Read:
    """A ``(texture or None, channel or None, factor)`` triple, checked."""
    if not isinstance(r, (tuple, list)) or len(r) != 3:
        raise ValueError(f"{name}: expected a (texture or None, channel or None, factor) triple, got {r!r}")
    t, c, f = r
    if t is not None and not isinstance(t, Texture):
        raise TypeError(f"{name}: expected a brdfpy.Texture or None, got {type(t).__name__}")
    if c is not None:
        if isinstance(c, bool) or not isinstance(c, (int, np.integer)):
            raise TypeError(f"{name}: the channel must be an integer or None, got {type(c).__name__}")
        if t is None or not 0 <= int(c) < t.channels:
            raise ValueError(f"{name}: channel {c} is not a channel of the texture")
        c = int(c)
    return (t, c, _factor3(name, f))


def _factor3(name: str, factor: ArrayLike) -> tuple[float, float, float]:
    try:
        f = np.asarray(factor, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name}: expected a number or three numbers, got {factor!r}") from e
    if f.size == 1:
        f = np.repeat(f, 3)
    if f.size != 3 or not np.isfinite(f).all() or (f < 0).any():
        raise ValueError(f"{name}: expected a finite factor ≥ 0 (one number or three), got {factor!r}")
    return (float(f[0]), float(f[1]), float(f[2]))


def _read(name: str, t: Any, factor: ArrayLike) -> _Read:
    if isinstance(t, TextureChannel):
        return (t.texture, t.index, _factor3(name, factor))
    if isinstance(t, Texture):
        return (t, None, _factor3(name, factor))
    raise TypeError(f"{name}: expected a brdfpy.Texture or tex.channel(k), got {type(t).__name__}")


def _read_of(name: str, x: Any) -> _Read:
    """A read of a texture, a scaled texture (``TextureSource.scaled``) or a constant."""
    if isinstance(x, TextureSource):
        if x.kind != "texture":
            raise ValueError(
                f"{name}: expected a texture, a scaled texture or a constant, got a {x.kind} source"
            )
        return x.reads[0]
    if isinstance(x, (Texture, TextureChannel)):
        return _read(name, x, 1.0)
    return (None, None, _factor3(name, x))


def _read_mean(r: _Read) -> NDArray[np.float64]:
    t, c, f = r
    if t is None:
        return np.asarray(f, dtype=np.float64)
    m = t.mean
    texel = np.asarray(m[:3] if c is None else (m[c],) * 3, dtype=np.float64)
    out: NDArray[np.float64] = texel * np.asarray(f, dtype=np.float64)
    return out


#: What a texture binding accepts.
TextureLike = Union[Texture, TextureChannel, TextureSource]


def source_args(name: str, t: Any) -> tuple[str, list[tuple[Any, int | None, tuple[float, float, float]]]]:
    """``(kind, reads)`` of a bound parameter's value, as the compiled renderer takes it."""
    if isinstance(t, TextureSource):
        return t._args()
    tex, channel = texture_read(name, t)
    return "texture", [(tex, channel, (1.0, 1.0, 1.0))]


def texture_read(name: str, t: Any) -> tuple[Any, int | None]:
    """``(compiled texture, channel or None)`` of a :class:`Texture` or :class:`TextureChannel`."""
    if isinstance(t, TextureChannel):
        return (t.texture._t, t.index)
    if isinstance(t, Texture):
        return (t._t, None)
    raise TypeError(
        f"{name}: expected a brdfpy.Texture (or tex.channel(k), a TextureSource), got {type(t).__name__}"
    )
