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
``baseColorFactor`` alpha (a primitive whose alpha is below ``alphaCutoff`` is not drawn; per-texel alpha
needs the base-colour texture, see below); ``BLEND`` is rendered opaque (brdfpy has no transparency),
noted in :attr:`SceneAsset.notes`. A primitive without a material gets the specification's default
material (white, metallic 1, roughness 1).

**Textures** (base colour, metallic-roughness, normal, occlusion, emissive; MTL ``map_Kd``, ``map_Bump``,
``norm``...) are read and kept, not yet applied to the scene's materials (:class:`brdfpy.Texture` renders
textures on meshes built by hand; mapping the files' texture slots onto it is still to do): each material's
:attr:`AssetMaterial.textures` holds them as :class:`TextureRef` (the encoded image bytes and MIME type,
sampler wrap modes and filters, texture-coordinate set, slot, scale or strength, colour space), and the
meshes' texture coordinates and tangents are in :attr:`AssetPart.uvs` and :attr:`AssetPart.tangents`. A
scene with texture references warns once (:class:`TexturesNotAppliedWarning`, "N textures not applied").

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
    """A scene's materials refer to textures, which are kept (:attr:`AssetMaterial.textures`) but not
    applied yet: the render shows the materials' constant factors."""


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
    base_color: ArrayLike, metallic: float, roughness: float
) -> tuple[Model, dict[str, Any]]:
    """The ``cook_torrance`` model of a glTF metallic-roughness material (see the module documentation:
    Appendix B with its diffuse not weighted by ``1 − F``), and its parameters."""
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
        When materials refer to textures (once per call).
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
    for name, raw, xf, mat_index, uvs, tangents, colors in raw_parts:
        mat = default if mat_index is None else materials[mat_index]
        if (
            mat.alpha_mode == "MASK"
            and mat.opacity < mat.alpha_cutoff
            and "baseColorTexture" not in mat.textures
        ):
            notes.append(
                f"{name}: alpha mode MASK with alpha {mat.opacity:g} < cutoff {mat.alpha_cutoff:g}: not drawn"
            )
            continue
        mesh = raw if isinstance(raw, Mesh) else Mesh._wrap(raw)
        world = stand @ np.asarray(xf, dtype=np.float64)
        inst = scene.add(mesh, mat.model, world, ambient=mat.ambient, emission=mat.emission)
        part = AssetPart(name, inst, mat_index, uvs, tangents, colors)
        if mat.double_sided:
            st = mesh.stats()
            if not (st["watertight"] and st["signed_volume"] > 0):
                back = mesh.copy().flip_winding()
                part.backside = scene.add(back, mat.model, world, ambient=mat.ambient, emission=mat.emission)
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

    n_tex = len(asset.textures)
    if n_tex:
        warnings.warn(
            f"{p}: {n_tex} textures not applied (scene-file textures are not mapped onto brdfpy.Texture "
            "yet); the materials' "
            "constant factors are rendered, the references are kept in scene.asset.materials[i].textures",
            TexturesNotAppliedWarning,
            stacklevel=2,
        )
    return scene, cameras
