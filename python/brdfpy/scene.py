""":class:`Scene`: meshes with materials and transforms, lights, ambient light and background, rendered on the
CPU by the tiled, multithreaded rasterizer of ``brdf-raster``.

Every surface follows the Phong illumination model (Phong 1975; in the form of Theoharis et al.,
*Graphics and Visualization*, 2008, ch. 12)::

    L = emission + ambient ∘ I_a · w(p) + Σ_j δ_j · E_j ∘ model.shade(l_j, v, n)

where ``ambient`` is the material's ambient reflectance ``k_a`` (by default what the material reflects under a
uniform white sky, its white-sky albedo, so that ``Scene(ambient_light=...)`` lights every object through its
own model), ``I_a`` the scene's ambient light, ``w(p)``
the ambient obscurance (1 unless ``ao`` is on), ``E_j`` and ``l_j`` what light ``j`` delivers at ``p``,
``δ_j`` its visibility (1 unless ``shadows`` is on) and ``model.shade`` the material's reflectance model
(``f_r · max(n·l, 0)`` for physical models, the course formula as written for classic ones). An environment
and area lights (:class:`brdfpy.SphereLight`, :class:`brdfpy.RectLight`) add the radiance they reflect,
``∫ L(l) V(p, l) f_r(l, v) cos θ_l dω`` (see :mod:`brdfpy.environment` and :mod:`brdfpy.lights`).
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterable, Mapping
from typing import Any, Callable, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import I64_MAX, I64_MIN, as_float, as_int
from brdfpy.camera import Camera
from brdfpy.environment import Environment
from brdfpy.image import Image
from brdfpy.lights import Light, color3
from brdfpy.mesh import Mesh, _mat4
from brdfpy.models import Model
from brdfpy.texture import Texture, TextureChannel, TextureSource, source_args, texture_read

__all__ = ["MAX_IMAGE_SIDE", "MAX_PIXELS", "OUTPUTS", "SHADING_MODES", "Instance", "ProgressBar", "Scene"]

#: Tone-mapping operators accepted by :meth:`Scene.render`.
TONEMAPS = ("clamp", "reinhard", "reinhard_extended", "aces")

#: The largest image :meth:`Scene.render` accepts: ``MAX_IMAGE_SIDE`` pixels wide or tall, and
#: ``MAX_PIXELS`` pixels in all (``width·height``, whatever the samples per pixel). Read from the renderer,
#: which is where the limits are defined and checked.
MAX_IMAGE_SIDE, MAX_PIXELS = _brdfpy.raster_limits()

#: The buffers :meth:`Scene.render` can write (``outputs=``), see :class:`Image`.
OUTPUTS = ("rgb", "hdr", "depth", "normal", "triangle_id")

#: What :meth:`Scene.render` writes unless told otherwise: the 8-bit image and the depth.
DEFAULT_OUTPUTS = ("rgb", "depth")

#: Shading algorithms accepted by :meth:`Scene.render` (flat, Gouraud 1971, Phong 1975, van Overveld &
#: Wyvill 1997).
SHADING_MODES = ("flat", "gouraud", "phong", "quadratic")

#: Default ambient-occlusion options (``ao=True``); ``d_max`` ``None`` means a quarter of the scene's
#: bounding-box diagonal.
AO_DEFAULTS: dict[str, Any] = {
    "tau": 2.0,
    "d_max": None,
    "samples": 64,
    "per_pixel": False,
    "seed": 0,
    "combined": False,
    "stored": False,
}

ProgressArg = Union[None, bool, Callable[[float], Any]]


class Instance:
    """One mesh placed in a scene: ``mesh``, ``material`` (a :class:`brdfpy.Model`), ``transform`` (4×4,
    object → world), ``ambient`` (``k_a``, linear RGB, or ``None`` for the material's white-sky albedo) and
    ``emission`` (linear RGB), and its maps: ``normal_map`` (with ``normal_scale``), ``occlusion_map`` (with
    ``occlusion_strength``), ``emission_map`` (a :class:`brdfpy.Texture` or ``None`` each) and ``alpha_mask``
    (with ``alpha_cutoff``). Returned by
    :meth:`Scene.add`; its attributes may be reassigned (they are checked again at render time)."""

    __slots__ = (
        "alpha_cutoff",
        "alpha_mask",
        "ambient",
        "emission",
        "emission_map",
        "material",
        "mesh",
        "normal_map",
        "normal_scale",
        "occlusion_map",
        "occlusion_strength",
        "transform",
    )

    def __init__(
        self, mesh: Mesh, material: Model, transform: NDArray[np.float64], ambient: Any, emission: Any
    ) -> None:
        self.mesh = mesh
        self.material = material
        self.transform = transform
        self.ambient = ambient
        self.emission = emission
        self.normal_map: Any = None
        self.normal_scale = 1.0
        self.occlusion_map: Any = None
        self.occlusion_strength = 1.0
        self.emission_map: Any = None
        self.alpha_mask: Any = None
        self.alpha_cutoff = 0.5

    def _texture_args(self) -> tuple[Any, ...] | None:
        """What the compiled renderer takes for this instance's textures, or ``None`` without any."""
        bound = getattr(self.material, "_textures", None) or {}
        maps = (self.normal_map, self.occlusion_map, self.emission_map, self.alpha_mask)
        if not bound and all(m is None for m in maps):
            return None
        params = [(k, *source_args(k, t)) for k, t in bound.items()]

        def opt(name: str, t: Any) -> tuple[Any, int | None] | None:
            return None if t is None else texture_read(name, t)

        return (
            params,
            opt("normal_map", self.normal_map),
            as_float("normal_scale", self.normal_scale),
            opt("occlusion_map", self.occlusion_map),
            as_float("occlusion_strength", self.occlusion_strength),
            opt("emission", self.emission_map),
            None if self.alpha_mask is None else _alpha_args(self.alpha_mask, self.alpha_cutoff),
        )

    def __repr__(self) -> str:
        return f"Instance({self.mesh!r}, material={self.material!r})"


def _alpha_args(mask: Any, cutoff: Any) -> tuple[Any, float]:
    """The compiled renderer's alpha-mask argument: one read (a channel, possibly scaled) and the cutoff."""
    if isinstance(mask, TextureChannel):
        mask = TextureSource.scaled(mask)
    if not isinstance(mask, TextureSource) or mask.kind != "texture" or mask.reads[0][0] is None:
        raise TypeError(
            "alpha_mask: expected tex.channel(k) or TextureSource.scaled(tex.channel(k), factor), got "
            f"{type(mask).__name__}"
        )
    _, reads = mask._args()
    return reads[0], as_float("alpha_cutoff", cutoff)


class ProgressBar:
    """A progress indication on stderr: ``label [#####.....]  52 %  1.3 s``, redrawn in place on a terminal,
    a few lines otherwise. Pass it (or ``progress=True``) to :meth:`Scene.render`. With ``delay`` (seconds),
    nothing is drawn until the render has run that long, so quick renders stay silent."""

    def __init__(
        self, label: str = "rendering", stream: Any = None, width: int = 30, delay: float = 0.0
    ) -> None:
        self.label = label
        self.delay = delay
        self.stream = sys.stderr if stream is None else stream
        self.width = width
        self.t0 = time.perf_counter()
        self._last = -1.0
        self._tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def __call__(self, fraction: float) -> None:
        if isinstance(fraction, bool) or not isinstance(fraction, (int, float, np.integer, np.floating)):
            raise TypeError(f"fraction: expected a number in [0, 1], got {type(fraction).__name__}")
        if not 0.0 <= fraction <= 1.0:
            raise ValueError(f"fraction: expected a number in [0, 1], got {fraction}")
        step = 0.02 if self._tty else 0.25
        if fraction < 1.0 and fraction - self._last < step:
            return
        if self._last < 0 and time.perf_counter() - self.t0 < self.delay:
            return  # short renders show no bar at all
        self._last = fraction
        filled = round(fraction * self.width)
        bar = "#" * filled + "." * (self.width - filled)
        dt = time.perf_counter() - self.t0
        line = f"{self.label} [{bar}] {100 * fraction:3.0f} %  {dt:.1f} s"
        if self._tty:
            self.stream.write("\r" + line + ("\n" if fraction >= 1.0 else ""))
        else:
            self.stream.write(line + "\n")
        self.stream.flush()


def _outputs(outputs: Any) -> list[str]:
    """The output names of ``Scene.render(outputs=...)``, checked."""
    if isinstance(outputs, str):
        names = list(OUTPUTS) if outputs == "all" else [outputs]
    else:
        try:
            names = list(outputs)
        except TypeError:
            raise TypeError(
                f"outputs: expected names from {OUTPUTS} (or 'all'), got {type(outputs).__name__}"
            ) from None
    for n in names:
        if not isinstance(n, str):
            raise TypeError(f"outputs: expected names from {OUTPUTS}, got an item of type {type(n).__name__}")
        if n not in OUTPUTS:
            raise ValueError(
                f"outputs: unknown output {n!r}; expected some of {', '.join(OUTPUTS)} (or 'all')"
            )
    if not names:
        raise ValueError(f"outputs: asks for nothing; name at least one of {', '.join(OUTPUTS)}")
    return names


def _int(name: str, x: Any) -> int:
    """An integer the compiled module can take (64-bit); its own range check names the argument after."""
    return as_int(name, x, I64_MIN, I64_MAX)


def _seed(name: str, x: Any) -> int:
    """A seed in [0, 2^64) (beyond the signed 64-bit range of :func:`_int`)."""
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
        raise TypeError(f"{name}: expected an integer, got {type(x).__name__}")
    k = int(x)
    if not 0 <= k < 2**64:
        shown = str(k) if k.bit_length() <= 128 else f"an integer of {k.bit_length()} bits"
        raise ValueError(f"{name}: must lie in [0, 2^64), got {shown}")
    return k


class Scene:
    """A scene to render: mesh instances (each with a material and a transform), lights, an ambient light
    and a background color.

    Parameters
    ----------
    ambient_light : number, three numbers or None
        ``I_a``, the radiance (linear RGB) of a uniform sky lighting every object: an object reflects
        ``ambient ∘ I_a`` (times the obscurance ``w(p)`` when rendering with ``ao``), where ``ambient`` is
        its own ``ambient=`` if :meth:`add` was given one, else its material's *white-sky albedo* — the
        cosine-weighted mean over view directions of what the model reflects under a uniform white sky
        (the bihemispherical reflectance of Nicodemus et al. 1977), computed by quadrature from the model
        itself: ``kd`` for Lambert, the copper colour (less the microfacet model's single-scattering loss)
        for a copper conductor. ``None`` (default): no ambient light; an object given ``ambient=`` then
        shows exactly that colour (``I_a = 1``), the others none.
    background : number or three numbers
        Linear RGB radiance where no surface is drawn. Black by default.
    environment : Environment, optional
        Light arriving from every direction (:class:`brdfpy.Environment`), lighting every object in the
        mode ``Scene.render(env_mode=...)`` asks for, and shown where no surface is drawn (in place of
        ``background``).

    Examples
    --------
    >>> scene = brdfpy.Scene()
    >>> red = brdfpy.model("blinn_phong_classic", kd=(0.8, 0.3, 0.2), ks=0.5, shininess=32)
    >>> scene.add(brdfpy.icosphere(5), red, ambient=(0.04, 0.015, 0.01))
    >>> scene.add_light(brdfpy.DirectionalLight((-1, -1, -1)))
    >>> scene.add_light(brdfpy.PointLight((2, 2, 2), intensity=10))
    >>> img = scene.render(brdfpy.Camera.perspective((0, 0, 3)), 640, 480)
    >>> img.save("sphere.png")
    """

    def __init__(
        self, *, ambient_light: Any = None, background: Any = 0.0, environment: Environment | None = None
    ) -> None:
        self.instances: list[Instance] = []
        self.lights: list[Light] = []
        self.ambient_light = ambient_light
        self.background = background
        self.environment = environment

    @property
    def environment(self) -> Environment | None:
        """The environment lighting the scene (and shown as its background), or ``None``."""
        return self._environment

    @environment.setter
    def environment(self, value: Environment | None) -> None:
        if value is not None and not isinstance(value, Environment):
            raise TypeError(f"environment: expected a brdfpy.Environment or None, got {type(value).__name__}")
        self._environment = value

    @property
    def ambient_light(self) -> tuple[float, float, float] | None:
        """``I_a`` (linear RGB), or ``None`` for no ambient light (see :class:`Scene`)."""
        return self._ambient_light

    @ambient_light.setter
    def ambient_light(self, value: Any) -> None:
        self._ambient_light = None if value is None else color3("ambient_light", value)

    @property
    def background(self) -> tuple[float, float, float]:
        """Background radiance (linear RGB)."""
        return self._background

    @background.setter
    def background(self, value: Any) -> None:
        self._background = color3("background", value)

    def add(
        self,
        mesh: Any,
        material: Model | str | None = None,
        transform: ArrayLike | None = None,
        *,
        ambient: Any = None,
        emission: Any = 0.0,
        normal_map: Texture | None = None,
        normal_scale: float = 1.0,
        occlusion_map: Texture | TextureChannel | None = None,
        occlusion_strength: float = 1.0,
        alpha_mask: TextureChannel | TextureSource | None = None,
        alpha_cutoff: float = 0.5,
    ) -> Instance:
        """Add a mesh with a material; returns its :class:`Instance`.

        Parameters
        ----------
        mesh : Mesh, or anything :meth:`Mesh.from_any` accepts (e.g. a trimesh mesh)
        material : Model or str, optional
            The reflectance model, from :func:`brdfpy.model`; a name means that model with its defaults.
            Default: ``brdfpy.model("lambert")``.
        transform : array_like (4, 4), optional
            Object → world matrix (column vectors, ``p_world = M @ p``), e.g. from :mod:`brdfpy.transforms`.
            Identity by default. Normals follow its inverse transpose; a mirroring matrix keeps the
            counter-clockwise side as the front.
        ambient : number, three numbers or None
            Ambient reflectance ``k_a`` (linear RGB), multiplied by the scene's ``ambient_light``
            (or shown as it is when the scene has none). ``None`` (default): the material's white-sky
            albedo under the scene's ``ambient_light`` (see :class:`Scene`), nothing without one. The
            canonical benchmark scene uses ``0.05·kd``.
        emission : number, three numbers or Texture
            Emitted radiance (linear RGB), added unlit; a :class:`brdfpy.Texture` emits its RGB (an emission
            map, glTF's ``emissiveTexture``; set :attr:`Instance.emission` to scale it).
        normal_map : Texture, optional
            A tangent-space normal map (glTF's ``normalTexture``, linear RGB: load 8-bit files with
            ``colorspace="linear"``): the shading normal becomes ``normalize(T·x·s + B·y·s + N·z)`` with
            ``(x, y, z) = 2·rgb − 1``, ``s = normal_scale``, ``N`` the interpolated normal, ``T`` the
            mesh's tangent and ``B = w·(N × T)``. A mesh without :attr:`Mesh.tangents` gets MikkTSpace
            tangents here (:meth:`Mesh.with_generated_tangents`); it needs :attr:`Mesh.uvs`.
        occlusion_map : Texture or Texture.channel(k), optional
            Ambient occlusion baked in texture space (glTF's ``occlusionTexture``, red channel unless a
            channel is chosen): the ambient and indirect terms are multiplied by
            ``1 + occlusion_strength·(r − 1)``. Shadows and ``ao`` are computed per pixel as ever.
        alpha_mask : Texture.channel(k) or TextureSource.scaled(tex.channel(k), factor), optional
            An alpha test (glTF's ``alphaMode: MASK``): a sample whose mask value (the channel at its
            texture coordinates, filtered like any texture, times the factor) is below ``alpha_cutoff`` is
            not drawn, so what lies behind shows through. It decides what is seen only: shadow and
            ambient-occlusion rays still meet the whole triangles.

        Textures (these maps and any texture-bound parameter of ``material``, see :func:`brdfpy.model`)
        are read at the perspective-correct texture coordinates of every shaded sample, in every shading
        mode (``"flat"`` and ``"gouraud"`` then evaluate the model per sample too, with the face normal and
        the interpolated vertex normal). A material with textures on a mesh without :attr:`Mesh.uvs` is
        refused at render time. With textured parameters the default ``ambient`` is the white-sky albedo
        of the model at the textures' means; environment and area lights see that model too.
        """
        # The scene keeps the mesh as it is now (a copy-on-write handle, no data copied).
        m = Mesh.from_any(mesh).copy()
        if material is None:
            material = Model("lambert")
        elif isinstance(material, str):
            material = Model(material)
        elif not isinstance(material, _brdfpy.Model):
            raise TypeError(
                f"material: expected a brdfpy.Model (from brdfpy.model(...)) or a model name, "
                f"got {type(material).__name__}"
            )
        xf = np.eye(4) if transform is None else np.array(_mat4("transform", transform)).reshape(4, 4)
        if abs(np.linalg.det(xf[:3, :3])) == 0:
            raise ValueError("transform: is singular (its 3×3 part has determinant 0)")
        ka = None if ambient is None else color3("ambient", ambient)
        emission_map = None
        if isinstance(emission, Texture):
            emission_map, emission = emission, 1.0
        if normal_map is not None:
            if not isinstance(normal_map, Texture):
                raise TypeError(f"normal_map: expected a brdfpy.Texture, got {type(normal_map).__name__}")
            if m.uvs is None:
                raise ValueError("normal_map: the mesh has no texture coordinates (Mesh(..., uvs=...))")
            m = m.with_generated_tangents()
        if occlusion_map is not None:
            texture_read("occlusion_map", occlusion_map)
        inst = Instance(m, material, xf, ka, color3("emission", emission))
        inst.normal_map, inst.normal_scale = normal_map, as_float("normal_scale", normal_scale)
        inst.occlusion_map = occlusion_map
        inst.occlusion_strength = as_float("occlusion_strength", occlusion_strength)
        inst.emission_map = emission_map
        if alpha_mask is not None:
            if m.uvs is None:
                raise ValueError("alpha_mask: the mesh has no texture coordinates (Mesh(..., uvs=...))")
            _alpha_args(alpha_mask, alpha_cutoff)
            inst.alpha_mask, inst.alpha_cutoff = alpha_mask, alpha_cutoff
        self.instances.append(inst)
        return inst

    def add_light(self, light: Light) -> Light:
        """Add a light (:class:`DirectionalLight`, :class:`PointLight`, :class:`SpotLight`, or an area light,
        :class:`SphereLight` or :class:`RectLight`); returns it."""
        if not isinstance(light, Light):
            raise TypeError(
                f"light: expected a brdfpy light (e.g. DirectionalLight), got {type(light).__name__}"
            )
        self.lights.append(light)
        return light

    def bounds(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """World-space axis-aligned bounding box ``(min, max)`` of every instance (corners of each mesh's
        box, transformed)."""
        if not self.instances:
            raise ValueError("scene: has no meshes")
        pts = []
        for inst in self.instances:
            lo, hi = inst.mesh.bounds()
            corners = np.array(
                [[x, y, z, 1.0] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
            )
            w = corners @ np.asarray(inst.transform, dtype=np.float64).T
            pts.append(w[:, :3] / w[:, 3:4])
        allp = np.concatenate(pts)
        return allp.min(axis=0), allp.max(axis=0)

    def render(
        self,
        camera: Camera,
        width: int = 800,
        height: int = 600,
        shading: str = "phong",
        *,
        cull_back_faces: bool = True,
        samples: int = 1,
        tonemap: str = "clamp",
        exposure: float = 0.0,
        white: float | None = None,
        ao: bool | Mapping[str, Any] | None = None,
        shadows: bool = False,
        progress: ProgressArg = None,
        outputs: str | Iterable[str] = DEFAULT_OUTPUTS,
        env_mode: str = "fast",
        env_samples: int = 64,
        env_seed: int = 0,
        area_samples: int = 16,
        area_seed: int = 0,
    ) -> Image:
        """Render the scene through ``camera`` into a ``width × height`` :class:`Image`.

        The scene is converted under the GIL, then rendered with the GIL released on brdfpy's thread pool
        (:func:`brdfpy.set_num_threads`); the result is bit-identical for any number of threads.

        The defaults make a *reference* render: one sample per pixel, no shadows, ``"clamp"`` (exactly
        the shading formula, each option a deliberate choice, and the canonical scene's check pixels).
        The ``brdfpy render`` command makes a *presentation* image instead (``samples=4``,
        ``shadows=True``, ``tonemap="aces"``, 1280×720); pass those arguments for the command's look.

        Parameters
        ----------
        camera : Camera
        width, height : int
            Image size in pixels: 1 to :data:`MAX_IMAGE_SIDE` (<MAX_IMAGE_SIDE>) each, and at most
            :data:`MAX_PIXELS` (<MAX_PIXELS>) pixels in all, at any number of ``samples`` (supersamples are
            drawn and resolved band by band, so memory grows with the pixel count, not the samples).
        shading : str
            The shading algorithm: ``"flat"`` (constant: once per triangle, face normal), ``"gouraud"``
            (Gouraud 1971: at the vertices, colors interpolated), ``"phong"`` (normal interpolated and
            renormalised, the model evaluated per pixel) or ``"quadratic"`` (van Overveld & Wyvill's
            quadratic normal interpolation, per pixel). The mode says where the *reflectance model* is
            evaluated; shadows and per-pixel obscurance are always computed per pixel (per sample), so a
            flat or Gouraud surface gets the same sharp shadow edges as a Phong one.
        cull_back_faces : bool
            Skip triangles seen from behind (clockwise on screen).
        samples : int
            Supersampling anti-aliasing: 1, 4, 9 or 16 samples per pixel on a regular grid, box-filtered.
        tonemap : str
            How :attr:`Image.rgb` maps HDR values into [0, 1]: ``"clamp"`` (default), ``"reinhard"``,
            ``"reinhard_extended"`` (with ``white``, default 4) or ``"aces"``; then sRGB and 8 bits.
        exposure : float
            Stops applied before tone mapping (``c · 2^exposure``).
        ao : bool or dict, optional
            Ambient obscurance ``w(p)`` (Zhukov, Iones & Kronin 1998; Theoharis et al. 2008, eqs.
            12.71–12.74) weighting the ambient term. ``True`` for
            the defaults, or a dict with any of ``tau`` (2: how quickly an occluder's weight grows with its
            distance), ``d_max`` (range beyond which nothing occludes; default a quarter of the scene's
            bounding-box diagonal), ``samples`` (64 rays per point), ``per_pixel`` (False: estimated at the
            vertices and interpolated; True: at every shaded point), ``seed`` (0) and ``combined`` (False;
            True adds the diffuse term ``k_d·I_d(p)·w(p)`` of Theoharis et al. 2008 eq. 12.75) and ``stored``
            (False; True: instances whose mesh holds a stored :attr:`Mesh.obscurance` use it, interpolated
            over the faces, instead of an estimate — self-occlusion baked in object space, not occlusion by
            the other objects; the other instances are estimated as usual).
        shadows : bool
            Cast shadow rays toward every point, spot and directional light (hard shadows; ``δ_j`` ∈ {0, 1}).
            Area lights always trace their visibility (soft shadows), whatever this says.
        progress : bool or callable, optional
            ``True`` draws a progress bar on stderr; a callable receives the fraction done (0–1, increasing),
            from a worker thread with the GIL held; an exception it raises is re-raised after the render.
        outputs : str or iterable of str
            The buffers to write, any of :data:`OUTPUTS` (``"rgb"``, ``"hdr"``, ``"depth"``, ``"normal"``,
            ``"triangle_id"``), or ``"all"``. Default ``("rgb", "depth")``: the displayable image and the
            depth (which also gives :attr:`Image.mask`). Writing fewer buffers is faster (at 1080p the HDR,
            normal and id buffers are 58 MB a frame); reading a buffer that was not rendered raises
            ``BrdfError`` naming it. :meth:`Image.tonemapped` needs ``"hdr"``.
        env_mode : str
            How the scene's :attr:`environment` lights it (see :mod:`brdfpy.environment`): ``"fast"``
            (spherical-harmonic irradiance and a prefiltered map, no noise, darkened by ``ao``) or
            ``"monte_carlo"`` (multiple importance sampling with ray-cast visibility, converging to the
            reflected radiance of the rendering equation).
        env_samples : int
            Monte Carlo iterations per shaded point (each one sample of the material's sampler and one of
            the environment's), 1 to 2^20; the noise falls as ``1/√env_samples``.
        env_seed : int
            Seed of the Monte Carlo mode's random numbers, in [0, 2^64).
        area_samples : int
            Monte Carlo iterations per shaded point (per sample of ``samples``) and area light
            (:class:`SphereLight`, :class:`RectLight`), each one sample of the light and one of the material
            combined by multiple importance sampling, 1 to 2^20; the noise falls as ``1/√area_samples``. Area
            lights always trace their visibility (soft shadows), whatever ``shadows`` says.
        area_seed : int
            Seed of the area lights' random numbers, in [0, 2^64): the same image for the same seed, at any
            number of threads.

        Raises
        ------
        ValueError
            Sizes out of range, unknown shading / tone map names, invalid AO options, non-finite or negative
            colors, singular transforms, a scene without meshes (the message names the argument).
        TypeError
            Arguments of the wrong type.
        """
        if not isinstance(camera, Camera):
            raise TypeError(f"camera: expected a brdfpy.Camera, got {type(camera).__name__}")
        w, h = _int("width", width), _int("height", height)
        n = _int("samples", samples)
        if not isinstance(shading, str):
            raise TypeError(f"shading: expected one of {SHADING_MODES}, got {type(shading).__name__}")
        if not isinstance(tonemap, str):
            raise TypeError(f"tonemap: expected a name, got {type(tonemap).__name__}")
        if tonemap.lower() not in TONEMAPS:
            raise ValueError(f"tonemap: expected one of {', '.join(TONEMAPS)}, got {tonemap!r}")
        if isinstance(exposure, bool) or not isinstance(exposure, (int, float, np.integer, np.floating)):
            raise TypeError(f"exposure: expected a number, got {type(exposure).__name__}")
        if not self.instances:
            raise ValueError("scene: has no meshes to render (use Scene.add)")
        ao_args = self._ao_args(ao)
        out_names = _outputs(outputs)
        if not isinstance(env_mode, str):
            raise TypeError(f"env_mode: expected 'fast' or 'monte_carlo', got {type(env_mode).__name__}")
        env_n, seed = _int("env_samples", env_samples), _seed("env_seed", env_seed)
        if not 1 <= env_n <= 2**20:
            raise ValueError(f"env_samples: must lie in [1, 2^20], got {env_n}")
        area_n, area_s = _int("area_samples", area_samples), _seed("area_seed", area_seed)
        if not 1 <= area_n <= 2**20:
            raise ValueError(f"area_samples: must lie in [1, 2^20], got {area_n}")
        cb: Callable[[float], Any] | None
        if progress is True:
            cb = ProgressBar()
        elif progress is None or progress is False:
            cb = None
        elif callable(progress):
            cb = progress
        else:
            raise TypeError(f"progress: expected a bool or a callable, got {type(progress).__name__}")
        instances = [
            (
                inst.mesh._m,
                inst.material,
                _mat4("transform", inst.transform),
                None if inst.ambient is None else color3("ambient", inst.ambient),
                color3("emission", inst.emission),
            )
            for inst in self.instances
        ]
        tex_args = [inst._texture_args() for inst in self.instances]
        textures = None if all(t is None for t in tex_args) else tex_args
        frame = _brdfpy.render_scene(
            instances,
            [light._l for light in self.lights if isinstance(light._l, _brdfpy.RasterLight)],
            self._ambient_light,
            self._background,
            camera._c,
            w,
            h,
            shading,
            bool(cull_back_faces),
            n,
            tonemap,
            as_float("exposure", exposure),
            None if white is None else as_float("white", white),
            ao_args,
            bool(shadows),
            cb,
            self._stored_obscurance(ao),
            out_names,
            None if self._environment is None else self._environment._e,
            env_mode,
            env_n,
            seed,
            [light._l for light in self.lights if isinstance(light._l, _brdfpy.RasterAreaLight)],
            area_n,
            area_s,
            textures,
        )
        return Image(frame)

    def _stored_obscurance(self, ao: bool | Mapping[str, Any] | None) -> list[Any] | None:
        """Each instance's stored per-vertex obscurance (or None) when ``ao`` asks for stored values."""
        if not isinstance(ao, Mapping) or not ao.get("stored", False):
            return None
        stored = [inst.mesh.obscurance for inst in self.instances]
        if all(w is None for w in stored):
            # Most likely computed on the mesh after Scene.add took its snapshot: say so, do not silently
            # estimate instead.
            raise ValueError(
                "ao stored: no instance's mesh has a stored obscurance; call mesh.compute_obscurance(..., "
                "store=True) before Scene.add(mesh), or on the added instance's mesh (Instance.mesh)"
            )
        return stored

    def _ao_args(
        self, ao: bool | Mapping[str, Any] | None
    ) -> tuple[float, float, int, int, bool, bool] | None:
        if ao is None or ao is False:
            return None
        opts = dict(AO_DEFAULTS)
        if ao is not True:
            if not isinstance(ao, Mapping):
                raise TypeError(f"ao: expected None, a bool or a dict of options, got {type(ao).__name__}")
            unknown = set(ao) - set(AO_DEFAULTS)
            if unknown:
                raise ValueError(f"ao: unknown option(s) {sorted(unknown)}; known: {sorted(AO_DEFAULTS)}")
            opts.update(ao)
        if opts["d_max"] is None:
            lo, hi = self.bounds()
            opts["d_max"] = max(0.25 * float(np.linalg.norm(hi - lo)), 1e-6)
        samples, seed = _int("ao samples", opts["samples"]), _int("ao seed", opts["seed"])
        if not 1 <= samples <= 65536:
            raise ValueError(f"ao samples: must lie in [1, 65536], got {samples}")
        if not 0 <= seed < 2**64:
            raise ValueError(f"ao seed: must lie in [0, 2^64), got {seed}")
        return (
            float(opts["tau"]),
            float(opts["d_max"]),
            samples,
            seed,
            bool(opts["per_pixel"]),
            bool(opts["combined"]),
        )

    def __repr__(self) -> str:
        faces = sum(i.mesh.n_faces for i in self.instances)
        return f"<brdfpy.Scene {len(self.instances)} instances ({faces} faces), {len(self.lights)} lights>"


# The limits in the docs are the renderer's own (one definition, in brdf-raster's `MAX_PIXELS`).
Scene.render.__doc__ = (
    (Scene.render.__doc__ or "")
    .replace("<MAX_IMAGE_SIDE>", str(MAX_IMAGE_SIDE))
    .replace("<MAX_PIXELS>", f"{MAX_PIXELS:,}")
)
