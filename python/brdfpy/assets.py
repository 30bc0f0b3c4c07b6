"""Scene files: :func:`load_scene` reads a glTF 2.0 scene (``.gltf`` with its ``.bin`` and image files or
data URIs, ``.glb``), an OBJ file with its MTL materials, or an STL or PLY mesh, into a :class:`brdfpy.Scene`
and its cameras. The files are decoded in Rust (``brdf-raster``'s glTF, OBJ/MTL, STL and PLY readers);
this module maps what they hold onto brdfpy's models, lights and cameras.

**glTF metallic-roughness materials** (Khronos, *glTF 2.0 Specification*, Appendix B, "BRDF
Implementation") become ``cook_torrance`` with

- ``distribution="ggx"`` (Trowbridge-Reitz) with ``roughness`` (brdfpy's α) = ``roughnessFactor²``,
- ``masking="smith"`` (the height-correlated Smith G of Appendix B, "Specular BRDF"),
- ``fresnel="schlick"`` with ``f0 = mix(0.04, baseColor, metallic)``, ``ks = 1``,
- ``kd = (1 − metallic)·baseColor`` (the diffuse term ``kd/π``).

The specular part is Appendix B's exactly: Appendix B mixes a dielectric layer (Schlick with F0 = 0.04)
and a metal (Schlick with F0 = baseColor) by ``metallic``, and Schlick's formula is linear in F0, so the
mixture of the two specular lobes *is* one lobe with ``F0 = mix(0.04, baseColor, metallic)``. **What
differs** is the diffuse term: Appendix B's ``fresnel_mix`` weights the dielectric's diffuse by
``1 − F_d(v·h)`` (``F_d`` Schlick with F0 = 0.04), giving ``(1 − metallic)(1 − F_d)·baseColor/π``; brdfpy's
``cook_torrance`` adds ``kd/π`` unweighted (its diffuse and specular are independent terms, as in Cook and
Torrance 1982), so its diffuse is brighter by ``(1 − metallic)·F_d(v·h)·baseColor/π``: 4 % of the diffuse at
normal incidence (``F_d(1) = 0.04``), growing toward grazing half-angles (``F_d → 1`` as ``v·h → 0``, where
the specular dominates anyway). The registry model has no diffuse-Fresnel weight, and adding one would change
``cook_torrance`` for every user; the tests compare against a NumPy transcription of Appendix B and check
that the difference is this term and nothing else.

Also mapped: ``emissiveFactor`` × ``KHR_materials_emissive_strength`` → the instance's ``emission``;
``COLOR_0`` → the mesh's vertex colours (they multiply the diffuse term: exact for dielectrics, while the
specification also tints a metal's F0 by them); ``doubleSided`` → a second instance with the winding
reversed (so both sides are lit, each with its own normal, under back-face culling; skipped for closed,
outward meshes, whose back is never seen from outside); alpha mode ``OPAQUE``; ``MASK`` with the constant
``baseColorFactor`` alpha (a primitive whose alpha is below ``alphaCutoff`` is not drawn) and, with an RGBA
base-colour texture, per texel: a sample whose ``alpha·factor`` is below the cutoff is not drawn
(``Scene.add(..., alpha_mask=)``, tested in the coverage pass, so what is behind shows through; shadows still
see the whole triangles); ``BLEND`` is rendered opaque (brdfpy has no transparency),
noted in :attr:`SceneAsset.notes`. A primitive without a material gets the specification's default
material (white, metallic 1, roughness 1).

**Textures** are decoded with Pillow (each image once) into :class:`brdfpy.Texture` with the file's sampler
(``wrapS``/``wrapT``; nearest for a ``NEAREST`` magnification filter, else trilinear when minification
uses mip-maps, else bilinear) and applied to the parts with texture coordinates (``TEXCOORD_0``): the
``baseColorTexture`` (sRGB) and ``metallicRoughnessTexture`` (linear, G = roughness, B = metalness) enter
Appendix B's mapping above per shaded point (:func:`metallic_roughness`: ``kd``, ``f0`` and ``roughness`` as
:class:`brdfpy.texture.TextureSource` values, each factor multiplying its texel); ``normalTexture`` (linear,
with its ``scale``) becomes the instance's normal map, with the file's tangents or MikkTSpace ones;
``occlusionTexture`` (R, with its ``strength``) its occlusion map; ``emissiveTexture`` (sRGB) its emission
map times ``emissiveFactor``. MTL maps multiply their constants, as the format says: ``map_Kd`` × ``Kd``
(the ``kd`` of ``blinn_phong``, or the base colour of a ``Pr``/``Pm`` material), ``map_Ks`` × ``Ks``,
``map_Ns`` × ``Ns`` (shininess, first channel), ``map_Ke`` × ``Ke``; ``norm`` is a tangent-space normal map;
``map_Bump`` / ``bump`` is read as a height map (one channel or grey, turned into a normal map by
:func:`height_to_normal_map` with ``-bm`` as the strength) or, when it is coloured, as the normal map many
exporters write under that name. Not applied, each listed in :attr:`SceneAsset.notes` with one
:class:`TexturesNotAppliedWarning` per load: a second texture-coordinate set, MTL ``-o``/``-s``,
``map_Ka``, ``map_d``, images that cannot be read, and textures of a mesh without texture coordinates.
The references as the file gives them stay in :attr:`AssetMaterial.textures`
(:class:`TextureRef`: encoded image bytes and MIME type, sampler, slot, scale or strength, colour space).

**Lights** (``KHR_lights_punctual``): brdfpy's lights already follow that extension's conventions (colour ×
intensity, direction of travel along the node's −z, spot half-angles), and its renderer works in relative
linear units, so the numbers are taken as they are: a point or spot light of ``I`` candela becomes a
:class:`brdfpy.PointLight` / :class:`brdfpy.SpotLight` of intensity ``I`` (its irradiance ``I/d²``), a
directional light of ``E`` lux a :class:`brdfpy.DirectionalLight` of irradiance ``E``. (The photometric →
radiometric factor 1/683 W/lm would only shift the exposure by −9.4 stops; like the Khronos sample viewer,
brdfpy leaves the choice of exposure to the user: ``exposure=`` of ``Scene.render``, ``--exposure``.) A
spot's ``innerConeAngle`` / ``outerConeAngle`` are its inner / outer half-angles; between them brdfpy fades
with a smoothstep in the cosine where the extension suggests the square of a linear ramp (the same ends,
slightly different shoulders). ``range`` is not applied (the inverse-square law holds at any distance, which
the extension allows: range is a cut-off for efficiency); it is kept in :attr:`SceneAsset.lights`.
**A file without lights** gets two directional lights placed relative to the view (a key light from
above-left behind the camera, irradiance 3, and a fill from the right, 0.8) and an ambient light of 0.1;
:attr:`SceneAsset.default_lights` says so.

**Cameras**: a perspective camera becomes :meth:`brdfpy.Camera.perspective` with ``fovy = yfov`` (in
degrees), ``near = znear`` and ``far = zfar`` (an infinite ``zfar`` becomes a far plane beyond the whole
scene); its ``aspectRatio`` is not part of a brdfpy camera (which takes the image's), so it is kept in
:attr:`SceneAsset.cameras` (``brdfpy render --scene`` sizes the image by it). An orthographic camera
becomes :meth:`brdfpy.Camera.orthographic` with ``height = 2·ymag`` (``xmag/ymag`` kept as its aspect).
The camera looks along its node's −z with +y up (scale is ignored; a mirroring camera node cannot be
expressed by a look-at camera and is noted). **A file without cameras** gets one framing the scene from
its front (+z, glTF's front, slightly above).

**Node transforms** compose parent × child into each primitive's world matrix (the instance's
``transform``). A mirroring transform (negative determinant) flips the winding, as the specification
requires; brdfpy's renderer does that for any instance whose transform mirrors, so the outside stays the
outside.

**OBJ + MTL** (Wavefront's MTL format): ``Kd``, ``Ks``, ``Ns`` become the normalised ``blinn_phong``
(``kd = Kd``, ``ks = Ks``, ``shininess = Ns``: the MTL exponent is already that of ``(n·h)^Ns``, illumination
model 2, so it is used as it is, clipped to the model's range [0, 10000]; colours clipped to [0, 1]); the
literal formula of the format is ``blinn_phong_classic`` with the same values (``Kd`` multiplying ``n·l``
without 1/π, π times brighter under the same light). ``illum 0`` (constant colour) gives ``emission = Kd``
and no reflection, ``illum 1`` no specular; ``Ka`` → the instance's ``ambient`` (× the scene's ambient
light), ``Ke`` → ``emission``; ``d`` < 1 (or ``Tr``) is rendered opaque (noted). Materials with the PBR
extension's ``Pr`` / ``Pm`` use the glTF mapping above with ``baseColor = Kd``. A missing MTL file or an
unknown ``usemtl`` name gives the default material, noted in :attr:`SceneAsset.skipped`.

**STL, PLY, and OBJ without materials**: one mesh with :data:`DEFAULT_MATERIAL` (a light grey dielectric:
glTF's mapping of baseColor 0.8, metallic 0, roughness 0.5).
"""

from __future__ import annotations

import io
import math
import os
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._paths import as_path
from brdfpy.camera import Camera
from brdfpy.lights import DirectionalLight, Light, PointLight, SpotLight
from brdfpy.mesh import Mesh, load_mesh
from brdfpy.models import Model, model
from brdfpy.scene import Instance, Scene
from brdfpy.texture import Texture, TextureSource, _image_array
from brdfpy.transforms import up_to_y

__all__ = [
    "DEFAULT_MATERIAL",
    "SCENE_EXTENSIONS",
    "AssetCamera",
    "AssetMaterial",
    "AssetPart",
    "ImageSource",
    "SceneAsset",
    "TextureRef",
    "TexturesNotAppliedWarning",
    "height_to_normal_map",
    "load_scene",
    "metallic_roughness",
]

#: The file extensions :func:`load_scene` reads.
SCENE_EXTENSIONS: tuple[str, ...] = (".gltf", ".glb", ".obj", ".stl", ".ply")

#: The metallic-roughness factors of the material given to STL and PLY meshes and OBJ faces without one.
DEFAULT_MATERIAL: dict[str, Any] = {"base_color": (0.8, 0.8, 0.8), "metallic": 0.0, "roughness": 0.5}

# Texture slots whose images hold colours (sRGB-encoded 8-bit images); the others hold linear data.
_SRGB_SLOTS = ("baseColorTexture", "emissiveTexture", "map_Kd", "map_Ks", "map_Ka", "map_Ke")


class TexturesNotAppliedWarning(UserWarning):
    """Some texture references of a scene's materials could not be applied (the reasons are in
    :attr:`SceneAsset.notes`); those slots render with the materials' constant factors."""


@dataclass(frozen=True)
class ImageSource:
    """An image a texture reads: glTF's encoded bytes (``data``, with ``mime_type``), or an MTL texture's
    file (``path``, not opened)."""

    name: str
    mime_type: str | None
    data: bytes | None
    path: str | None

    def read(self) -> bytes:
        """The encoded image bytes (from the file for an MTL texture)."""
        if self.data is not None:
            return self.data
        assert self.path is not None
        with open(self.path, "rb") as f:
            return f.read()


@dataclass(frozen=True)
class TextureRef:
    """A material's reference to a texture, as the file gives it.

    ``slot``: glTF's ``baseColorTexture``, ``metallicRoughnessTexture`` (G = roughness, B = metalness),
    ``normalTexture``, ``occlusionTexture`` (R), ``emissiveTexture``, or the MTL statement (``map_Kd``,
    ``map_Ks``, ``map_Ns``, ``map_d``, ``map_Ka``, ``map_Ke``, ``map_Bump``, ``norm``). ``scale``: the normal
    map's scale, the occlusion strength, an MTL ``-bm`` (else 1). ``wrap_s`` / ``wrap_t``: ``"REPEAT"``,
    ``"CLAMP_TO_EDGE"`` or ``"MIRRORED_REPEAT"``; ``mag_filter`` ``"LINEAR"`` or ``"NEAREST"``; ``mipmaps``
    whether minification uses mip-maps. ``color_space``: ``"srgb"`` for colour slots, ``"linear"`` for data.
    ``uv_offset`` / ``uv_scale``: MTL ``-o`` / ``-s`` (glTF: 0 and 1). ``tex_coord``: the ``TEXCOORD_n`` set.
    """

    slot: str
    image: ImageSource
    texture: int | None
    tex_coord: int
    scale: float
    wrap_s: str
    wrap_t: str
    mag_filter: str
    mipmaps: bool
    color_space: str
    uv_offset: tuple[float, float] = (0.0, 0.0)
    uv_scale: tuple[float, float] = (1.0, 1.0)


@dataclass
class AssetMaterial:
    """A material of the file and the brdfpy model it became (see the module documentation).

    ``factors`` holds the file's values as read (glTF: ``base_color`` RGBA, ``metallic``, ``roughness``,
    ``emissive``; MTL: ``Ka``, ``Kd``, ``Ks``, ``Ke``, ``Ns``, ``d``, ``illum``, ``Pr``, ``Pm``)."""

    name: str
    model: Model
    emission: tuple[float, float, float]
    ambient: tuple[float, float, float] | None
    double_sided: bool
    alpha_mode: str
    alpha_cutoff: float
    opacity: float
    textures: dict[str, TextureRef]
    source: str
    factors: dict[str, Any] = field(default_factory=dict)


@dataclass
class AssetPart:
    """One primitive (glTF) or material group (OBJ) as placed in the scene: its :class:`brdfpy.Instance`
    (``instance.transform`` is the node's world matrix), the index of its material in
    :attr:`SceneAsset.materials` (``None``: the default material), and the file's texture coordinates
    ``uvs`` (V, 2; glTF's origin, the image's top left), ``tangents`` (V, 4: xyz and the handedness w) and
    vertex ``colors`` (V, 3), each ``None`` when absent. ``backside``: the reversed copy drawn for a
    double-sided material, if any."""

    name: str
    instance: Instance
    material: int | None
    uvs: NDArray[np.float32] | None = None
    tangents: NDArray[np.float32] | None = None
    colors: NDArray[np.float32] | None = None
    backside: Instance | None = None


@dataclass
class AssetCamera:
    """A camera of the file: ``camera`` (the brdfpy camera), ``kind`` (``"perspective"`` or
    ``"orthographic"``), ``aspect`` (the file's width / height, or ``None``), ``transform`` (camera →
    world, after ``up``), and the file's own values in ``values`` (``yfov`` [rad], ``znear``, ``zfar``,
    ``xmag``, ``ymag``)."""

    name: str
    camera: Camera
    kind: str
    aspect: float | None
    transform: NDArray[np.float64]
    values: dict[str, Any]


@dataclass
class SceneAsset:
    """What :func:`load_scene` read, beside the scene it built (``scene.asset``)."""

    path: str
    format: str
    parts: list[AssetPart]
    materials: list[AssetMaterial]
    default_material: AssetMaterial
    cameras: list[AssetCamera]
    lights: list[dict[str, Any]]
    default_lights: bool
    default_camera: bool
    skipped: list[str]
    notes: list[str]

    @property
    def textures(self) -> list[tuple[AssetMaterial, TextureRef]]:
        """Every texture reference of the materials the parts use, with its material."""
        used = {p.material for p in self.parts}
        mats = [self.default_material if i is None else self.materials[i] for i in sorted(used, key=_key)]
        return [(m, t) for m in mats for t in m.textures.values()]


def _key(i: int | None) -> int:
    return -1 if i is None else i


class _AssetScene(Scene):
    """A :class:`brdfpy.Scene` with the :class:`SceneAsset` it came from (``scene.asset``)."""

    def __init__(self, asset: SceneAsset, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.asset = asset


# -- materials ------------------------------------------------------------------------------------------


def metallic_roughness(
    base_color: ArrayLike,
    metallic: float,
    roughness: float,
    *,
    base_color_texture: Texture | None = None,
    metallic_roughness_texture: Texture | None = None,
) -> tuple[Model, dict[str, Any]]:
    """The ``cook_torrance`` model of a glTF metallic-roughness material (see the module documentation:
    Appendix B with its diffuse not weighted by ``1 − F``), and its parameters.

    ``base_color`` (RGB), ``metallic`` and ``roughness`` are glTF's factors; with ``base_color_texture``
    (sRGB RGB or RGBA) the base colour is ``factor ∘ texel``, with ``metallic_roughness_texture`` (linear; G =
    roughness, B = metalness) the metalness and roughness are the factors times its B and G. The model is
    then a :class:`brdfpy.TexturedModel`: ``kd`` = ``(1 − metallic)·baseColor``, ``f0`` =
    ``mix(0.04, baseColor, metallic)`` and ``roughness`` = ``(G·roughnessFactor)²`` per shaded point
    (:class:`brdfpy.texture.TextureSource`)."""
    base = np.clip(np.asarray(base_color, dtype=np.float64).reshape(-1)[:3], 0.0, 1.0)
    m = float(np.clip(metallic, 0.0, 1.0))
    r = float(np.clip(roughness, 0.0, 1.0))
    params: dict[str, Any] = {
        "kd": tuple(float(x) for x in (1.0 - m) * base),
        "ks": 1.0,
        "distribution": "ggx",
        "roughness": r * r,
        "masking": "smith",
        "fresnel": "schlick",
        "f0": tuple(float(x) for x in 0.04 * (1.0 - m) + base * m),
    }
    if base_color_texture is not None or metallic_roughness_texture is not None:
        base_read: Any = tuple(float(x) for x in base)
        metal_read: Any = m
        if base_color_texture is not None:
            base_read = TextureSource.scaled(base_color_texture, base_read)
        mr = metallic_roughness_texture
        if mr is not None:
            if mr.channels < 3:
                raise ValueError(
                    f"metallic_roughness_texture: needs G (roughness) and B (metalness), got a "
                    f"{mr.channels}-channel texture"
                )
            metal_read = TextureSource.scaled(mr.channel(2), m)
            params["roughness"] = TextureSource.squared(mr.channel(1), r)
        params["kd"] = TextureSource.metallic_diffuse(base_read, metal_read)
        params["f0"] = TextureSource.metallic_f0(base_read, metal_read)
    return model("cook_torrance", **params), params


def _default_material() -> AssetMaterial:
    mdl, _ = metallic_roughness(DEFAULT_MATERIAL["base_color"], 0.0, DEFAULT_MATERIAL["roughness"])
    return AssetMaterial(
        "default",
        mdl,
        (0.0, 0.0, 0.0),
        None,
        False,
        "OPAQUE",
        0.5,
        1.0,
        {},
        "default",
        dict(DEFAULT_MATERIAL),
    )


def _gltf_material(d: dict[str, Any], data: dict[str, Any]) -> AssetMaterial:
    base = d["base_color"]
    mdl, _ = metallic_roughness(base[:3], d["metallic"], d["roughness"])
    textures: dict[str, TextureRef] = {}
    for slot, ref in d["textures"].items():
        tex = data["textures"][ref["texture"]]
        img = data["images"][tex["image"]]
        textures[slot] = TextureRef(
            slot=slot,
            image=ImageSource(img["name"], img["mime_type"], img["data"], None),
            texture=int(ref["texture"]),
            tex_coord=int(ref["tex_coord"]),
            scale=float(ref["scale"]),
            wrap_s=tex["wrap_s"],
            wrap_t=tex["wrap_t"],
            mag_filter=tex["mag_filter"],
            mipmaps=bool(tex["mipmaps"]),
            color_space="srgb" if slot in _SRGB_SLOTS else "linear",
        )
    factors = {k: d[k] for k in ("base_color", "metallic", "roughness", "emissive")}
    return AssetMaterial(
        name=d["name"],
        model=mdl,
        emission=_rgb(d["emissive"]),
        ambient=None,
        double_sided=bool(d["double_sided"]),
        alpha_mode=d["alpha_mode"],
        alpha_cutoff=float(d["alpha_cutoff"]),
        opacity=float(base[3]),
        textures=textures,
        source="gltf",
        factors=factors,
    )


def _rgb(x: Any) -> tuple[float, float, float]:
    return (float(x[0]), float(x[1]), float(x[2]))


def _mtl_material(d: dict[str, Any], notes: list[str]) -> AssetMaterial:
    name = d["name"]
    kd = np.array(d["Kd"] if d["Kd"] is not None else (0.8, 0.8, 0.8), dtype=np.float64)
    ks = np.array(d["Ks"] if d["Ks"] is not None else (0.0, 0.0, 0.0), dtype=np.float64)
    for label, c in (("Kd", kd), ("Ks", ks)):
        if (c > 1).any():
            notes.append(f"newmtl {name}: {label} {c.tolist()} clipped to [0, 1]")
    kd, ks = np.clip(kd, 0, 1), np.clip(ks, 0, 1)
    ns = float(d["Ns"]) if d["Ns"] is not None else 0.0
    illum = d["illum"]
    emission = _rgb(d["Ke"]) if d["Ke"] is not None else (0.0, 0.0, 0.0)
    if d["Pr"] is not None or d["Pm"] is not None:
        rough = d["Pr"] if d["Pr"] is not None else 0.5
        mdl, _ = metallic_roughness(kd, d["Pm"] or 0.0, rough)
    elif illum == 0:
        mdl = model("lambert", kd=0.0)
        emission = (emission[0] + float(kd[0]), emission[1] + float(kd[1]), emission[2] + float(kd[2]))
    else:
        spec = (0.0, 0.0, 0.0) if illum == 1 else tuple(float(x) for x in ks)
        mdl = model(
            "blinn_phong",
            kd=tuple(float(x) for x in kd),
            ks=spec,
            shininess=min(max(ns, 0.0), 10000.0),
        )
    if illum is not None and illum > 2:
        notes.append(f"newmtl {name}: illum {illum} (reflection/refraction) rendered as illum 2")
    opacity = float(d["d"]) if d["d"] is not None else 1.0
    if opacity < 1:
        notes.append(f"newmtl {name}: d = {opacity} rendered opaque (brdfpy has no transparency)")
    textures: dict[str, TextureRef] = {}
    for t in d["textures"]:
        slot = t["slot"]
        wrap = "CLAMP_TO_EDGE" if t["clamp"] else "REPEAT"
        textures[slot] = TextureRef(
            slot=slot,
            image=ImageSource(t["file"], _mime(t["file"]), None, os.fspath(t["path"])),
            texture=None,
            tex_coord=0,
            scale=float(t["bump_multiplier"]),
            wrap_s=wrap,
            wrap_t=wrap,
            mag_filter="LINEAR",
            mipmaps=True,
            color_space="srgb" if slot in _SRGB_SLOTS else "linear",
            uv_offset=(float(t["offset"][0]), float(t["offset"][1])),
            uv_scale=(float(t["scale"][0]), float(t["scale"][1])),
        )
    factors = {k: d[k] for k in ("Ka", "Kd", "Ks", "Ke", "Ns", "d", "illum", "Pr", "Pm")}
    ka = None if d["Ka"] is None else _rgb(d["Ka"])
    return AssetMaterial(name, mdl, emission, ka, False, "OPAQUE", 0.5, opacity, textures, "mtl", factors)


def _mime(name: str) -> str | None:
    ext = os.path.splitext(name)[1].lower()
    return {".png": "image/png", ".jpg": "image/jpeg", ".jpeg": "image/jpeg"}.get(ext)


# -- textures -------------------------------------------------------------------------------------------

_WRAP_NAMES = {"REPEAT": "repeat", "CLAMP_TO_EDGE": "clamp", "MIRRORED_REPEAT": "mirror"}


@dataclass
class _Maps:
    """A material's model with its textures applied, and the maps of its instances."""

    model: Model
    normal: tuple[Texture, float] | None = None
    occlusion: tuple[Any, float] | None = None
    emission: Texture | None = None
    alpha: tuple[TextureSource, float] | None = None
    applied: int = 0
    skipped: list[str] = field(default_factory=list)


class _TextureCache:
    """Decodes each image once per colour space, sampler and channel need (Pillow, as
    :meth:`brdfpy.Texture.from_bytes`)."""

    def __init__(self) -> None:
        self._cache: dict[tuple[Any, ...], Texture | str] = {}

    def get(self, ref: TextureRef, rgb: bool = False) -> Texture | str:
        """The texture, or why it cannot be read. ``rgb``: a 1-channel image is widened to RGB (a
        metallic-roughness texture saved as grey)."""
        # One filter serves magnification and minification: NEAREST magnification is asked for by pixel
        # art, which wants no blending either way; else mip-mapped minification decides.
        filt = "nearest" if ref.mag_filter == "NEAREST" else ("trilinear" if ref.mipmaps else "bilinear")
        wrap = (_WRAP_NAMES.get(ref.wrap_s, "repeat"), _WRAP_NAMES.get(ref.wrap_t, "repeat"))
        key = (ref.image, ref.color_space, wrap, filt, rgb)
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        out: Texture | str
        try:
            a = _image_array(io.BytesIO(ref.image.read()))
            if rgb and a.ndim == 2:
                a = np.repeat(a[..., None], 3, axis=2)
            out = Texture(a, wrap=wrap, filter=filt, colorspace=ref.color_space)
        except (OSError, ValueError, TypeError) as e:  # a missing file, an image Pillow cannot decode
            out = f"image {ref.image.name!r} not read ({e})"
        self._cache[key] = out
        return out


def _is_height_map(t: Texture) -> bool:
    """Whether an MTL ``map_Bump`` image holds heights rather than a tangent-space normal map: one channel,
    or grey RGB (a normal map's blue, its z, is near 1 where red and green are near ½)."""
    if t.channels == 1:
        return True
    r, g, b, _ = t.mean
    return abs(r - g) < 0.02 and abs(g - b) < 0.02


def height_to_normal_map(height: Texture, strength: float = 1.0) -> Texture:
    """A tangent-space normal map (linear RGB, glTF's convention: +x right, +y up the image) of a height map
    ``h`` in [0, 1] (its first channel): ``n = normalize(−s·∂h/∂x, −s·∂h/∂y, 1)`` stored as ``(n + 1)/2``,
    with central differences in texel units (wrapping as the height map wraps) and ``s = strength`` (MTL's
    ``-bm``)."""
    h = height.levels()[0][..., 0].astype(np.float64)
    wrap = height.wrap if isinstance(height.wrap, tuple) else (height.wrap, height.wrap)
    mode = {"repeat": "wrap", "mirror": "symmetric", "clamp": "edge"}
    hp = np.pad(h, ((0, 0), (1, 1)), mode=mode[wrap[0]])  # type: ignore[call-overload]
    hp = np.pad(hp, ((1, 1), (0, 0)), mode=mode[wrap[1]])  # type: ignore[call-overload]
    dx = (hp[1:-1, 2:] - hp[1:-1, :-2]) / 2
    dy_up = (hp[:-2, 1:-1] - hp[2:, 1:-1]) / 2  # rows grow downward; +y of a normal texel is up
    n = np.stack([-strength * dx, -strength * dy_up, np.ones_like(h)], -1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return Texture((n * 0.5 + 0.5).astype(np.float32), wrap=wrap, filter=height.filter, colorspace="linear")


def _textured(mat: AssetMaterial, cache: _TextureCache) -> _Maps:
    """``mat`` with the textures it refers to applied (see the module documentation)."""
    out = _Maps(mat.model)
    tex: dict[str, Texture] = {}
    for slot, ref in mat.textures.items():
        if ref.tex_coord != 0:
            out.skipped.append(f"{slot}: reads TEXCOORD_{ref.tex_coord} (only TEXCOORD_0 is read)")
            continue
        if ref.uv_offset != (0.0, 0.0) or ref.uv_scale != (1.0, 1.0):
            out.skipped.append(f"{slot}: texture-coordinate offset/scale (-o/-s) is not applied")
            continue
        got = cache.get(ref, rgb=slot == "metallicRoughnessTexture")
        if isinstance(got, str):
            out.skipped.append(f"{slot}: {got}")
            continue
        tex[slot] = got

    def use(slot: str) -> Texture | None:
        t = tex.pop(slot, None)
        out.applied += t is not None
        return t

    f = mat.factors
    if mat.source == "gltf" or (mat.source == "mtl" and (f.get("Pr") is not None or f.get("Pm") is not None)):
        if mat.source == "gltf":
            base, metal, rough = f["base_color"][:3], f["metallic"], f["roughness"]
        else:
            base = np.clip(f["Kd"] if f["Kd"] is not None else (0.8, 0.8, 0.8), 0, 1)
            metal, rough = f["Pm"] or 0.0, f["Pr"] if f["Pr"] is not None else 0.5
        base_tex = use("baseColorTexture") or use("map_Kd")
        mr_tex = use("metallicRoughnessTexture")
        if mat.alpha_mode == "MASK" and base_tex is not None and base_tex.channels == 4:
            out.alpha = (TextureSource.scaled(base_tex.channel(3), mat.opacity), mat.alpha_cutoff)
        if base_tex is not None or mr_tex is not None:
            out.model, _ = metallic_roughness(
                base, metal, rough, base_color_texture=base_tex, metallic_roughness_texture=mr_tex
            )
    elif mat.model.name == "blinn_phong":
        p = dict(mat.model.params)
        kd, ks, ns = use("map_Kd"), use("map_Ks"), use("map_Ns")
        # MTL: a map multiplies its constant (map_Kd × Kd, map_Ks × Ks, map_Ns × Ns).
        if kd is not None:
            p["kd"] = TextureSource.scaled(kd, p["kd"])
        if ks is not None and max(p["ks"]) > 0:
            p["ks"] = TextureSource.scaled(ks, p["ks"])
        if ns is not None:
            p["shininess"] = TextureSource.scaled(ns.channel(0), p["shininess"])
        if kd is not None or ks is not None or ns is not None:
            out.model = model("blinn_phong", **p)
    elif mat.model.name == "lambert" and "map_Kd" in tex:  # MTL illum 0: Kd is the emitted colour
        out.emission = use("map_Kd")
    normal = use("normalTexture") or use("norm")
    if normal is not None:
        scale = mat.textures["normalTexture" if "normalTexture" in mat.textures else "norm"].scale
        out.normal = (normal, scale if mat.source == "gltf" else 1.0)
    bump = use("map_Bump") or use("bump")
    if bump is not None and out.normal is None:
        strength = mat.textures["map_Bump" if "map_Bump" in mat.textures else "bump"].scale
        out.normal = (height_to_normal_map(bump, strength), 1.0) if _is_height_map(bump) else (bump, 1.0)
    occ = use("occlusionTexture")
    if occ is not None:
        out.occlusion = (occ.channel(0), mat.textures["occlusionTexture"].scale)
    emissive = use("emissiveTexture") or use("map_Ke")
    if emissive is not None:
        out.emission = emissive
    for slot in tex:
        why = {
            "map_Ka": "per-texel ambient reflectance is not supported",
            "map_d": "brdfpy has no transparency",
        }.get(slot, "not used by this material's model")
        out.skipped.append(f"{slot}: {why}")
    return out


# -- cameras and lights ---------------------------------------------------------------------------------


def _bounds_sphere(scene: Scene) -> tuple[NDArray[np.float64], float]:
    lo, hi = scene.bounds()
    center = (lo + hi) / 2
    return center, max(float(np.linalg.norm(hi - lo)) / 2, 1e-6)


def _gltf_camera(
    c: dict[str, Any], stand: NDArray[np.float64], scene: Scene, notes: list[str]
) -> AssetCamera:
    m = stand @ np.asarray(c["transform"], dtype=np.float64)
    eye = m[:3, 3]
    lin = m[:3, :3]
    forward = lin @ np.array([0.0, 0.0, -1.0])
    up = lin @ np.array([0.0, 1.0, 0.0])
    name = c["name"]
    if not (np.linalg.norm(forward) > 0 and np.linalg.norm(up) > 0):
        raise ValueError(f"camera {name!r}: its node's transform is singular (no view direction)")
    if np.linalg.det(lin) < 0:
        notes.append(
            f"camera {name!r}: its node mirrors; a look-at camera cannot, so the image is not mirrored"
        )
    forward /= np.linalg.norm(forward)
    up /= np.linalg.norm(up)
    center, radius = _bounds_sphere(scene)
    reach = float(np.linalg.norm(center - eye)) + radius
    depth = float(np.dot(center - eye, forward))
    target = eye + forward * (depth if depth > 1e-6 else 1.0)
    values = {k: v for k, v in c.items() if k not in ("name", "transform", "type")}
    if c["type"] == "perspective":
        near = float(c["znear"])
        far = float(c["zfar"]) if c["zfar"] is not None else max(2.0 * reach, 1000.0 * near)
        cam = Camera.perspective(eye, target, up, math.degrees(float(c["yfov"])), near, far)
        aspect = None if c["aspect"] is None else float(c["aspect"])
    else:
        far = float(c["zfar"])
        near = max(float(c["znear"]), far * 1e-6)
        cam = Camera.orthographic(eye, target, up, 2.0 * float(c["ymag"]), near, far)
        aspect = float(c["xmag"]) / float(c["ymag"]) if float(c["ymag"]) > 0 else None
    return AssetCamera(name, cam, c["type"], aspect, m, values)


def _gltf_light(d: dict[str, Any], stand: NDArray[np.float64], notes: list[str]) -> Light:
    rot = stand[:3, :3]
    pos = tuple(float(x) for x in stand[:3, :3] @ np.array(d["position"]) + stand[:3, 3])
    direction = tuple(float(x) for x in rot @ np.array(d["direction"]))
    inten = _rgb(d["intensity"])
    if d["range"] is not None:
        notes.append(f"light {d['name']!r}: range {d['range']:g} not applied (inverse-square everywhere)")
    if d["type"] == "directional":
        return DirectionalLight(direction, intensity=inten)
    if d["type"] == "point":
        return PointLight(pos, intensity=inten)
    inner, outer = math.degrees(d["inner_cone_angle"]), math.degrees(d["outer_cone_angle"])
    return SpotLight(pos, direction, inten, min(inner, outer), outer)


def _default_lights(camera: Camera) -> list[Light]:
    """A key light from above left behind the camera and a fill from the right, relative to the view."""
    eye, target, up = (np.array(x) for x in (camera.eye, camera.target, camera.up))
    f = target - eye
    f /= np.linalg.norm(f)
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    key = -(-0.8 * f + 1.0 * u - 0.6 * r)  # travels away from a point above-left, behind the camera
    fill = -(-1.0 * f + 0.9 * r + 0.1 * u)
    return [DirectionalLight(tuple(key), intensity=3.0), DirectionalLight(tuple(fill), intensity=0.8)]


# -- loading --------------------------------------------------------------------------------------------


def _add_part(scene: Scene, m: Mesh, world: NDArray[np.float64], mat: AssetMaterial, maps: _Maps) -> Instance:
    """Add one part with its material's model and maps."""
    inst = scene.add(
        m,
        maps.model,
        world,
        ambient=mat.ambient,
        emission=mat.emission if maps.emission is None else maps.emission,
        normal_map=None if maps.normal is None else maps.normal[0],
        normal_scale=1.0 if maps.normal is None else maps.normal[1],
        occlusion_map=None if maps.occlusion is None else maps.occlusion[0],
        occlusion_strength=1.0 if maps.occlusion is None else maps.occlusion[1],
        alpha_mask=None if maps.alpha is None else maps.alpha[0],
        alpha_cutoff=0.5 if maps.alpha is None else maps.alpha[1],
    )
    if maps.emission is not None:  # the map times the material's factor (glTF emissiveFactor, MTL Ke)
        inst.emission = mat.emission
    return inst


def load_scene(
    path: str | os.PathLike[str],
    *,
    up: str = "y",
    transform: ArrayLike | None = None,
    lights: str = "auto",
    aspect: float = 16 / 9,
) -> tuple[Scene, list[Camera]]:
    """Load a scene file into a :class:`brdfpy.Scene` and its cameras (see the module documentation for
    what is mapped and how).

    Parameters
    ----------
    path : str or os.PathLike
        A ``.gltf`` (with its ``.bin`` and image files beside it, or data URIs), ``.glb``, ``.obj`` (with
        the ``.mtl`` files its ``mtllib`` names), ``.stl`` or ``.ply`` file.
    up : {"y", "-y", "z", "-z", "x", "-x"}
        The file's up axis, turned to brdfpy's +y (:func:`brdfpy.transforms.up_to_y`); glTF is +y up by
        its specification, STL and many OBJ files are z-up.
    transform : array_like (4, 4), optional
        A further world transform (after ``up``), e.g. ``brdfpy.transforms.rotate((0, 1, 0), 30)``.
        ``up`` and ``transform`` move everything in the file: meshes, lights and cameras.
    lights : {"auto", "file", "default", "none"}
        ``"auto"``: the file's lights, or the default lights (see the module documentation) when it has
        none; ``"file"``: the file's only; ``"default"``: the default lights instead of the file's.
    aspect : float
        Width / height of the image the default camera frames the scene for (when the file has none).

    Returns
    -------
    (Scene, list of Camera)
        The scene (its ``asset`` attribute is the :class:`SceneAsset`: materials with their texture
        references, parts with their UVs and tangents, the file's cameras and lights, notes) and the
        file's cameras in node order; a single framing camera when the file has none
        (``scene.asset.default_camera``).

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        An unsupported extension, or a malformed file (``BrdfError``: the message names the file and the
        element, e.g. ``meshes[0].primitives[0].attributes.POSITION``).

    Warns
    -----
    TexturesNotAppliedWarning
        When texture references cannot be applied (once per call; each is in ``scene.asset.notes``): a
        ``TEXCOORD_1`` set, a mesh without texture coordinates, an image that cannot be read or decoded, MTL
        ``map_Ka`` / ``map_d`` / ``-o`` / ``-s``.
    """
    p = as_path("path", path)
    if not os.path.exists(p):
        raise FileNotFoundError(f"path: no such file: {p!r}")
    if os.path.isdir(p):
        raise IsADirectoryError(f"path: is a directory: {p!r}")
    ext = os.path.splitext(p)[1].lower()
    if ext not in SCENE_EXTENSIONS:
        raise ValueError(
            f"path: unsupported scene file type {ext!r} (expected {', '.join(SCENE_EXTENSIONS)})"
        )
    if not isinstance(lights, str) or lights not in ("auto", "file", "default", "none"):
        raise ValueError(f"lights: expected 'auto', 'file', 'default' or 'none', got {lights!r}")
    stand = up_to_y(up)
    if transform is not None:
        xf = np.asarray(transform, dtype=np.float64)
        if xf.shape != (4, 4) or not np.isfinite(xf).all():
            raise ValueError(f"transform: expected a finite 4×4 matrix, got shape {xf.shape}")
        stand = xf @ stand
    notes: list[str] = []
    default = _default_material()
    materials: list[AssetMaterial]
    file_lights: list[dict[str, Any]] = []
    file_cameras: list[dict[str, Any]] = []
    skipped: list[str]
    raw_parts: list[tuple[Any, ...]]
    if ext in (".gltf", ".glb"):
        fmt = "gltf"
        data = _brdfpy.load_gltf(p)
        materials = [_gltf_material(d, data) for d in data["materials"]]
        gltf_default = _gltf_material(data["default_material"], data)
        raw_parts = [
            (d["name"], d["mesh"], d["transform"], d["material"], d["uvs"], d["tangents"], d["colors"])
            for d in data["primitives"]
        ]
        file_lights, file_cameras, skipped = data["lights"], data["cameras"], list(data["skipped"])
        default = gltf_default
    elif ext == ".obj":
        fmt = "obj"
        data = _brdfpy.load_obj_scene(p)
        materials = [_mtl_material(d, notes) for d in data["materials"]]
        raw_parts = [
            (d["name"], d["mesh"], np.eye(4), d["material"], d["uvs"], None, None) for d in data["parts"]
        ]
        skipped = list(data["skipped"])
    else:
        fmt = ext[1:]
        mesh = load_mesh(p, orient="keep")
        if mesh.is_inward():
            mesh.flip_winding()
            notes.append(f"{os.path.basename(p)}: closed and wound inward; its winding was reversed")
        raw_parts = [(os.path.basename(p), mesh._m, np.eye(4), None, None, None, mesh.colors)]
        materials, skipped = [], []

    scene = _AssetScene(
        SceneAsset(p, fmt, [], materials, default, [], file_lights, False, False, skipped, notes)
    )
    asset = scene.asset
    cache = _TextureCache()
    textured: dict[int, _Maps] = {}
    not_applied: list[str] = []
    for name, raw, xf, mat_index, uvs, tangents, colors in raw_parts:
        mat = default if mat_index is None else materials[mat_index]
        if mat.alpha_mode == "MASK" and mat.opacity < mat.alpha_cutoff:
            # No texel exceeds 1: the factor's alpha alone leaves nothing to draw.
            notes.append(
                f"{name}: alpha mode MASK with alpha {mat.opacity:g} < cutoff {mat.alpha_cutoff:g}: not drawn"
            )
            continue
        mesh = raw if isinstance(raw, Mesh) else Mesh._wrap(raw)
        world = stand @ np.asarray(xf, dtype=np.float64)
        maps = _Maps(mat.model)
        if mat.textures and mesh.uvs is None:
            not_applied += [f"{name}: {slot}: the mesh has no texture coordinates" for slot in mat.textures]
        elif mat.textures:
            if id(mat) not in textured:
                textured[id(mat)] = _textured(mat, cache)
                not_applied += [f"material {mat.name!r}: {why}" for why in textured[id(mat)].skipped]
            maps = textured[id(mat)]

        part = AssetPart(name, _add_part(scene, mesh, world, mat, maps), mat_index, uvs, tangents, colors)
        if mat.double_sided:
            st = mesh.stats()
            if not (st["watertight"] and st["signed_volume"] > 0):
                part.backside = _add_part(scene, mesh.copy().flip_winding(), world, mat, maps)
        asset.parts.append(part)
    if not asset.parts:
        raise ValueError(f"{p}: nothing to draw ({'; '.join(notes) or 'no triangles'})")
    for mat in {id(m): m for m in [default, *materials]}.values():
        if mat.alpha_mode == "BLEND":
            notes.append(f"material {mat.name!r}: alpha mode BLEND rendered opaque")

    cameras: list[Camera] = []
    for c in file_cameras:
        ac = _gltf_camera(c, stand, scene, notes)
        asset.cameras.append(ac)
        cameras.append(ac.camera)
    if not cameras:
        center, radius = _bounds_sphere(scene)
        cam = Camera.framing(center, radius, (0.0, 0.35, 1.0), fovy=40.0, aspect=aspect, margin=1.05)
        cameras.append(cam)
        asset.default_camera = True

    if lights in ("auto", "file"):
        for d in file_lights:
            scene.add_light(_gltf_light(d, stand, notes))
    if lights == "default" or (lights == "auto" and not file_lights):
        for light in _default_lights(cameras[0]):
            scene.add_light(light)
        scene.ambient_light = 0.1
        asset.default_lights = True

    asset.notes.extend(not_applied)
    if not_applied:
        warnings.warn(
            f"{p}: {len(not_applied)} texture reference(s) not applied ({'; '.join(not_applied[:3])}"
            f"{'; ...' if len(not_applied) > 3 else ''}); they are listed in scene.asset.notes",
            TexturesNotAppliedWarning,
            stacklevel=2,
        )
    return scene, cameras
