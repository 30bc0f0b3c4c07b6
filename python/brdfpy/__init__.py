"""brdfpy: fast reflectance models (BRDFs) with a Rust core and a NumPy API.

Conventions, everywhere: directions point away from the surface (``l`` toward the light, ``v`` toward the
viewer, ``n`` the unit normal, ``h = normalize(l + v)``, ``r = 2(n·l)n − l``); ``Model.eval`` is the BRDF
value ``f_r`` in 1/sr without the cosine and ``Model.shade`` what a renderer multiplies by the light's
color; colors are linear RGB, clamping and tone mapping are explicit steps.

>>> import brdfpy
>>> m = brdfpy.model("lambert", kd=0.5)
>>> m.eval([0, 0, 1], [0, 0, 1], [0, 0, 1])
array([0.15915494, 0.15915494, 0.15915494], dtype=float32)
"""

from __future__ import annotations

import os

from brdfpy import checks, fresnel, measured, microfacet, sampling, sh, tonemap, transforms, vectors, views
from brdfpy._brdfpy import BrdfError, __version__, get_num_threads, set_num_threads
from brdfpy._brdfpy import _reset_after_fork as _reset_after_fork
from brdfpy.assets import SceneAsset, TexturesNotAppliedWarning, load_scene
from brdfpy.camera import Camera
from brdfpy.environment import Environment
from brdfpy.image import Image
from brdfpy.lights import (
    AreaLight,
    DirectionalLight,
    Light,
    PointLight,
    RectLight,
    SphereLight,
    SpotLight,
)
from brdfpy.mesh import (
    BUILTIN_MESHES,
    InwardMeshWarning,
    Mesh,
    builtin_mesh,
    cube,
    icosphere,
    load_mesh,
    open_box,
    plane,
    polygon_normal,
    torus,
)
from brdfpy.models import Model, ModelInfo, ParamInfo, TexturedModel, model, model_info, models
from brdfpy.raycast import Hits, RayCaster
from brdfpy.scene import Instance, Scene
from brdfpy.texture import Texture, TextureChannel, TextureSource

__all__ = [
    "BUILTIN_MESHES",
    "AreaLight",
    "BrdfError",
    "Camera",
    "DirectionalLight",
    "Environment",
    "Hits",
    "Image",
    "Instance",
    "InwardMeshWarning",
    "Light",
    "Mesh",
    "Model",
    "ModelInfo",
    "ParamInfo",
    "PointLight",
    "RayCaster",
    "RectLight",
    "Scene",
    "SceneAsset",
    "SphereLight",
    "SpotLight",
    "Texture",
    "TextureChannel",
    "TextureSource",
    "TexturedModel",
    "TexturesNotAppliedWarning",
    "__version__",
    "builtin_mesh",
    "checks",
    "cube",
    "explore",
    "fresnel",
    "get_num_threads",
    "icosphere",
    "load_mesh",
    "load_scene",
    "measured",
    "microfacet",
    "model",
    "model_info",
    "models",
    "open_box",
    "plane",
    "polygon_normal",
    "sampling",
    "set_num_threads",
    "sh",
    "tonemap",
    "torus",
    "transforms",
    "vectors",
    "views",
]


def explore(models: Model | str | list[Model | str] | None = None, *, size: int = 512) -> object:
    """The interactive BRDF explorer for a Jupyter notebook (display the returned Panel layout), on the
    optional extra ``brdfpy[explore]``; ``brdfpy explore`` serves the same page in the browser. ``models``:
    a model, a name, or a list of them (default ``cook_torrance``)."""
    from brdfpy import explorer, views

    ms = [] if models is None else views._models(models)[0]
    return explorer.notebook(ms, size=size)


# The worker threads of the pool exist only in the process that started them; a forked child starts afresh.
if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_reset_after_fork)
