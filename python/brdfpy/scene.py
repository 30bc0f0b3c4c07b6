""":class:`Scene`: meshes with materials and transforms, lights, ambient light and background, rendered on the
CPU by the tiled, multithreaded rasterizer of ``brdf-raster``.

Every surface follows the Phong illumination model (seed 004, SPEC row 14)::

    L = emission + ambient ∘ I_a · w(p) + Σ_j δ_j · E_j ∘ model.shade(l_j, v, n)

where ``ambient`` is the material's ambient reflectance ``k_a``, ``I_a`` the scene's ambient light, ``w(p)``
the ambient obscurance (1 unless ``ao`` is on), ``E_j`` and ``l_j`` what light ``j`` delivers at ``p``,
``δ_j`` its visibility (1 unless ``shadows`` is on) and ``model.shade`` the material's reflectance model
(``f_r · max(n·l, 0)`` for physical models, the course formula as written for classic ones).
"""

from __future__ import annotations

import sys
import time
from collections.abc import Mapping
from typing import Any, Callable, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy.camera import Camera
from brdfpy.image import Image
from brdfpy.lights import Light, color3
from brdfpy.mesh import Mesh, _mat4
from brdfpy.models import Model

__all__ = ["SHADING_MODES", "Instance", "ProgressBar", "Scene"]

#: Tone-mapping operators accepted by :meth:`Scene.render`.
TONEMAPS = ("clamp", "reinhard", "reinhard_extended", "aces")

#: Shading algorithms of seed 004 accepted by :meth:`Scene.render`.
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
    object → world), ``ambient`` (``k_a``, linear RGB) and ``emission`` (linear RGB). Returned by
    :meth:`Scene.add`; its attributes may be reassigned (they are checked again at render time)."""

    __slots__ = ("ambient", "emission", "material", "mesh", "transform")

    def __init__(
        self, mesh: Mesh, material: Model, transform: NDArray[np.float64], ambient: Any, emission: Any
    ) -> None:
        self.mesh = mesh
        self.material = material
        self.transform = transform
        self.ambient = ambient
        self.emission = emission

    def __repr__(self) -> str:
        return f"Instance({self.mesh!r}, material={self.material!r})"


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


def _int(name: str, x: Any) -> int:
    if isinstance(x, bool) or not isinstance(x, (int, np.integer)):
        raise TypeError(f"{name}: expected an integer, got {type(x).__name__}")
    return int(x)


class Scene:
    """A scene to render: mesh instances (each with a material and a transform), lights, an ambient light
    and a background color.

    Parameters
    ----------
    ambient_light : number or three numbers
        ``I_a``, the ambient light (linear RGB) that each material's ``ambient`` reflectance multiplies.
        1 (white) by default, so that ``ambient`` is directly the ambient color a surface shows.
    background : number or three numbers
        Linear RGB radiance where no surface is drawn. Black by default.

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

    def __init__(self, *, ambient_light: Any = 1.0, background: Any = 0.0) -> None:
        self.instances: list[Instance] = []
        self.lights: list[Light] = []
        self.ambient_light = ambient_light
        self.background = background

    @property
    def ambient_light(self) -> tuple[float, float, float]:
        """``I_a`` (linear RGB)."""
        return self._ambient_light

    @ambient_light.setter
    def ambient_light(self, value: Any) -> None:
        self._ambient_light = color3("ambient_light", value)

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
        ambient: Any = 0.0,
        emission: Any = 0.0,
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
        ambient : number or three numbers
            Ambient reflectance ``k_a`` (linear RGB), multiplied by the scene's ``ambient_light``. The
            canonical benchmark scene uses ``0.05·kd``.
        emission : number or three numbers
            Emitted radiance (linear RGB), added unlit.
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
        inst = Instance(m, material, xf, color3("ambient", ambient), color3("emission", emission))
        self.instances.append(inst)
        return inst

    def add_light(self, light: Light) -> Light:
        """Add a light (:class:`DirectionalLight`, :class:`PointLight` or :class:`SpotLight`); returns it."""
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
    ) -> Image:
        """Render the scene through ``camera`` into a ``width × height`` :class:`Image`.

        The scene is converted under the GIL, then rendered with the GIL released on brdfpy's thread pool
        (:func:`brdfpy.set_num_threads`); the result is bit-identical for any number of threads.

        Parameters
        ----------
        camera : Camera
        width, height : int
            Image size in pixels, 1–16384 each, and at most 2^28 samples (``width·height·samples``).
        shading : str
            Seed 004's shading algorithms: ``"flat"`` (constant: once per triangle, face normal),
            ``"gouraud"`` (at the vertices, colors interpolated), ``"phong"`` (normal interpolated and
            renormalised, the model evaluated per pixel) or ``"quadratic"`` (van Overveld & Wyvill's
            quadratic normal interpolation, per pixel).
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
            Ambient obscurance ``w(p)`` (seed 004 eq. 12.71–12.74) weighting the ambient term. ``True`` for
            the defaults, or a dict with any of ``tau`` (2: how quickly an occluder's weight grows with its
            distance), ``d_max`` (range beyond which nothing occludes; default a quarter of the scene's
            bounding-box diagonal), ``samples`` (64 rays per point), ``per_pixel`` (False: estimated at the
            vertices and interpolated; True: at every shaded point), ``seed`` (0) and ``combined`` (False;
            True adds eq. 12.75's diffuse term ``k_d·I_d(p)·w(p)``) and ``stored`` (False; True: instances
            whose mesh holds a stored :attr:`Mesh.obscurance` use it, interpolated over the faces, instead
            of an estimate — self-occlusion baked in object space, not occlusion by the other objects;
            the other instances are estimated as usual).
        shadows : bool
            Cast shadow rays toward every light (hard shadows; ``δ_j`` ∈ {0, 1}).
        progress : bool or callable, optional
            ``True`` draws a progress bar on stderr; a callable receives the fraction done (0–1, increasing),
            from a worker thread with the GIL held; an exception it raises is re-raised after the render.

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
                color3("ambient", inst.ambient),
                color3("emission", inst.emission),
            )
            for inst in self.instances
        ]
        frame = _brdfpy.render_scene(
            instances,
            [light._l for light in self.lights],
            self._ambient_light,
            self._background,
            camera._c,
            w,
            h,
            shading,
            bool(cull_back_faces),
            n,
            tonemap,
            float(exposure),
            None if white is None else float(white),
            ao_args,
            bool(shadows),
            cb,
            self._stored_obscurance(ao),
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
