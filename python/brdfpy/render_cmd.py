"""``brdfpy render``: render a built-in scene, the canonical benchmark scene, a user's OBJ/PLY/STL mesh, or a
scene file (``--scene FILE``: glTF 2.0 ``.gltf``/``.glb``, OBJ with its MTL materials, STL, PLY; see
:func:`brdfpy.load_scene`) to PNG.

The built-in scene (no files needed): a gold Cook-Torrance icosphere, a red normalised Blinn-Phong torus and
Garland's cow (embedded CC0 mesh) in Oren-Nayar clay on a Lambertian floor, lit by a warm key light, a cool
fill light and an orange spot from behind, with soft ambient light, shadows and 2×2 supersampling.
"""

from __future__ import annotations

import argparse
import math
import os
import textwrap
import time
from typing import Any

import numpy as np

from brdfpy import tonemap as _tonemap
from brdfpy.assets import SCENE_EXTENSIONS, load_scene
from brdfpy.assets import _default_lights as _view_lights
from brdfpy.camera import Camera
from brdfpy.lights import DirectionalLight, Light, PointLight, SpotLight
from brdfpy.mesh import BUILTIN_MESHES, Mesh, builtin_mesh, icosphere, load_mesh, plane, torus
from brdfpy.models import model, models
from brdfpy.scene import SHADING_MODES, ProgressBar, Scene
from brdfpy.transforms import UP_AXES, rotate, scale, translate, up_to_y

__all__ = ["LIGHT_SYNTAX", "NEGATIVE_VALUE_FLAGS", "add_parser", "build_scene", "canonical_scene", "run"]

#: Flags whose values may start with a minus sign (the CLI glues them to the flag for argparse).
NEGATIVE_VALUE_FLAGS = ("--light", "--eye", "--target", "--exposure", "--up", "--rotate")

SCENES = ("builtin", "canonical")


def _floats(text: str, what: str, n: int) -> tuple[float, ...]:
    try:
        vals = tuple(float(p) for p in text.split(","))
    except ValueError:
        vals = ()
    if len(vals) == 1 and n == 3:
        vals = vals * 3
    if len(vals) != n or not all(math.isfinite(v) for v in vals):
        raise ValueError(f"{what}: expected {n} comma-separated numbers, got {text!r}")
    return vals


#: The ``--light`` syntax of ``brdfpy render`` (``brdfpy gallery`` takes its ``dir:`` and ``from:`` kinds).
LIGHT_SYNTAX = (
    "dir:DX,DY,DZ[:R,G,B] (a directional light travelling along DX,DY,DZ), from:X,Y,Z[:R,G,B] (the same "
    "light given by the direction toward it), point:X,Y,Z[:R,G,B] (a point light at X,Y,Z), "
    "spot:X,Y,Z:DX,DY,DZ[:R,G,B[:INNER,OUTER]] (a spot at X,Y,Z shining along DX,DY,DZ, half-angles in "
    "degrees). R,G,B is what the light emits, colour × intensity: the irradiance of a directional light "
    "(default 1), the radiant intensity of a point or spot light (default 10)"
)


def parse_light(text: str, kinds: tuple[str, ...] = ("dir", "from", "point", "spot")) -> Light:
    """A ``--light`` value (see :data:`LIGHT_SYNTAX`); every direction is the direction the light
    travels, except ``from:``, which names the direction toward the light. ``kinds`` restricts the
    accepted kinds."""
    parts = text.split(":")
    kind = {"directional": "dir", "toward": "from"}.get(parts[0].strip().lower(), parts[0].strip().lower())
    try:
        if kind in kinds and kind in ("dir", "from") and len(parts) in (2, 3):
            color = _floats(parts[2], "--light color", 3) if len(parts) == 3 else (1.0, 1.0, 1.0)
            d = _floats(parts[1], "--light direction", 3)
            if kind == "from":
                d = (-d[0] + 0.0, -d[1] + 0.0, -d[2] + 0.0)  # + 0.0: no -0 in messages
            return DirectionalLight(d, color)
        if kind in kinds and kind == "point" and len(parts) in (2, 3):
            inten = _floats(parts[2], "--light intensity", 3) if len(parts) == 3 else (10.0, 10.0, 10.0)
            return PointLight(_floats(parts[1], "--light position", 3), inten)
        if kind in kinds and kind == "spot" and len(parts) in (3, 4, 5):
            inten = _floats(parts[3], "--light intensity", 3) if len(parts) >= 4 else (10.0, 10.0, 10.0)
            inner, outer = _floats(parts[4], "--light angles", 2) if len(parts) == 5 else (20.0, 30.0)
            return SpotLight(
                _floats(parts[1], "--light position", 3),
                _floats(parts[2], "--light direction", 3),
                inten,
                inner,
                outer,
            )
    except ValueError as e:
        raise ValueError(f"--light {text!r}: {e}") from None
    forms = {
        "dir": "dir:DX,DY,DZ[:R,G,B] (direction of travel)",
        "from": "from:X,Y,Z[:R,G,B] (direction toward the light)",
        "point": "point:X,Y,Z[:R,G,B]",
        "spot": "spot:X,Y,Z:DX,DY,DZ[:R,G,B[:IN,OUT]]",
    }
    expected = ", ".join(forms[k] for k in kinds)
    hint = ""
    if len(parts) == 1 and len(parts[0].split(",")) == 3:
        # A bare direction is ambiguous (toward the light, or the way it travels?): make the user say which.
        hint = f"; a bare direction is ambiguous: write dir:{text} or from:{text}"
    raise ValueError(f"--light: expected {expected}, got {text!r}{hint}")


def parse_rotation(text: str) -> Any:
    """A ``--rotate`` value: ``DEG`` (about the vertical axis, +y, after ``--up``), or ``AXIS:DEG`` with
    ``AXIS`` one of x, y, z or three comma-separated numbers; degrees counter-clockwise (right-hand rule)."""
    axis_text, sep, deg_text = text.rpartition(":")
    axes = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}
    try:
        degrees = float(deg_text)
    except ValueError:
        degrees = math.nan
    if not math.isfinite(degrees):
        raise ValueError(f"--rotate: expected DEG or AXIS:DEG (e.g. 180 or x:-90), got {text!r}")
    if not sep:
        return rotate(axes["y"], degrees)
    key = axis_text.strip().lower()
    axis = axes[key] if key in axes else _floats(axis_text, "--rotate axis", 3)
    if not any(axis):
        raise ValueError(f"--rotate: the axis must not be zero, got {text!r}")
    return rotate(axis, degrees)


def stand_transform(up: str = "y", rotations: list[str] | None = None) -> Any:
    """The rotation ``--up`` and ``--rotate`` ask for: :func:`brdfpy.transforms.up_to_y` of ``up``, then
    each rotation in order (see :func:`parse_rotation`)."""
    m = up_to_y(up)
    for text in rotations or []:
        m = parse_rotation(text) @ m
    return m


def parse_value(text: str) -> Any:
    """A ``--param`` value: true/false, a number, comma-separated numbers, or a name."""
    low = text.strip().lower()
    if low in ("true", "false"):
        return low == "true"
    parts = [p.strip() for p in text.split(",")]
    try:
        nums = [float(p) for p in parts]
    except ValueError:
        return text.strip()
    return nums[0] if len(nums) == 1 else nums


def parse_params(items: list[str]) -> dict[str, Any]:
    """``--param KEY=VALUE`` items as a dict (numbers, comma-separated colors, true/false, names)."""
    out: dict[str, Any] = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise ValueError(f"--param: expected KEY=VALUE (e.g. roughness=0.2), got {item!r}")
        out[key.strip()] = parse_value(value)
    return out


# -- scenes -------------------------------------------------------------------------------------------------


def _default_lights() -> list[Light]:
    return [
        # Warm key light from the upper left front, cool fill from the right, orange spot from behind.
        DirectionalLight((0.55, -1.0, -0.6), (2.6, 2.3, 2.0)),
        PointLight((4.0, 2.5, 3.5), (14.0, 17.0, 24.0)),
        SpotLight((-1.0, 4.0, -4.0), (0.25, -0.8, 1.0), (45.0, 28.0, 12.0), 18.0, 32.0),
    ]


def _floor(scene: Scene, y: float, size: float) -> None:
    scene.add(
        plane(size, 48),
        model("lambert", kd=(0.30, 0.30, 0.32)),
        translate(0.0, y, 0.0),
    )


def _scene_option(text: str) -> str:
    """``--scene``: ``builtin``, ``canonical``, or a scene file (by its extension)."""
    if text in SCENES:
        return text
    if os.path.splitext(text)[1].lower() in SCENE_EXTENSIONS:
        return text
    raise argparse.ArgumentTypeError(
        f"expected builtin, canonical or a scene file ({', '.join(SCENE_EXTENSIONS)}), got {text!r}"
    )


def build_file_scene(args: argparse.Namespace) -> tuple[Scene, Camera]:
    """The scene of ``--scene FILE`` and its camera: the file's camera ``--camera N`` (default the first),
    or, when the file has none or ``--up``/``--rotate`` turn the scene and no ``--camera`` is given, a
    camera framing it from the front. ``--light`` replaces the file's (or the default) lights, ``--model``
    every material. Without ``--size`` a file camera's aspect ratio sets the image height."""
    if args.mesh is not None:
        raise ValueError("--scene FILE and --mesh: give one of them (--mesh renders one mesh on a floor)")
    turned = args.up != "y" or bool(args.rotate)
    stand = stand_transform(args.up, args.rotate)
    try:
        scene, _ = load_scene(
            args.scene,
            transform=stand,
            lights="none" if args.light else "auto",
            aspect=args.width / args.height,
        )
    except FileNotFoundError:
        raise FileNotFoundError(f"--scene: no such file: {args.scene!r}") from None
    asset = scene.asset  # type: ignore[attr-defined]
    n = len(asset.cameras)
    if args.camera is not None and not 0 <= args.camera < max(n, 1):
        raise ValueError(f"--camera: the file has {n} camera(s) (0..{n - 1}), got {args.camera}")
    if args.camera is not None and n == 0:
        raise ValueError(f"--camera: {args.scene} has no cameras")
    if n and (args.camera is not None or not turned):
        chosen = asset.cameras[args.camera or 0]
        cam = chosen.camera
        if args.size is None and chosen.aspect:
            args.height = max(1, round(args.width / chosen.aspect))
        asset.notes.append(f"camera {args.camera or 0} of {n}: {chosen.name!r}")
    else:
        lo, hi = scene.bounds()
        center, radius = (lo + hi) / 2, max(float(np.linalg.norm(hi - lo)) / 2, 1e-6)
        cam = Camera.framing(
            center, radius, (0.0, 0.35, 1.0), fovy=args.fovy, aspect=args.width / args.height
        )
        asset.notes.append(
            "framing camera (the file has none)" if n == 0 else "framing camera (--up/--rotate)"
        )
    if asset.default_lights:
        scene.lights = _view_lights(cam)
        asset.notes.append("no lights in the file: a key and a fill light relative to the view, ambient 0.1")
    if args.light:
        for light in (parse_light(t) for t in args.light):
            scene.add_light(light)
    if args.model is not None:
        mat = model(args.model, **parse_params(args.param))
        for inst in scene.instances:
            inst.material = mat
    elif args.param:
        raise ValueError("--param: name the --model the parameters belong to (it replaces every material)")
    if args.smooth is not None:
        for inst in scene.instances:
            inst.mesh.compute_normals(args.smooth)
    if args.eye is not None or args.target is not None:
        eye = _floats(args.eye, "--eye", 3) if args.eye is not None else cam.eye
        target = _floats(args.target, "--target", 3) if args.target is not None else cam.target
        cam = Camera.perspective(eye, target, fovy=args.fovy, near=cam.near, far=cam.far)
    return scene, cam


def build_scene(args: argparse.Namespace) -> tuple[Scene, Camera]:
    """The scene and camera the options ask for (built-in, canonical, ``--mesh``, or ``--scene FILE``)."""
    if args.scene not in SCENES:
        return build_file_scene(args)
    aspect = args.width / args.height
    if args.param and args.model is None and args.mesh is None:
        raise ValueError(
            f"--param: the {args.scene} scene has several materials; name the --model that the parameters "
            "belong to (it replaces every material), e.g. --model cook_torrance --param roughness=0.1"
        )
    if args.scene == "canonical":
        scene, cam = canonical_scene(args.level, args.model and model(args.model, **parse_params(args.param)))
        return scene, cam
    scene = Scene(ambient_light=(0.10, 0.11, 0.13), background=(0.015, 0.017, 0.022))
    if args.mesh is not None:
        # orient="keep": the --flip rule below decides (and says nothing to a CLI user).
        mesh = _load_mesh_option(args.mesh)
        if args.flip or (args.flip is None and mesh.stats()["signed_volume"] < 0):
            mesh.flip_winding()  # wound inward: back-face culling would show its inside
        if args.smooth is not None:
            mesh.compute_normals(args.smooth)
        stand = stand_transform(args.up, args.rotate)
        center, radius = mesh.transformed(stand).bounding_sphere()
        xf = scale(1.0 / radius) @ translate(-center) @ stand
        lo = (mesh.transformed(xf).bounds()[0])[1]
        xf = translate(0.0, -lo, 0.0) @ xf  # rest on the floor at y = 0
        # The model's own defaults (cook_torrance's are a red plastic), each --param changing one of them:
        # no defaults of the command's own that a --param or naming the model would silently drop.
        mat = model(args.model or "cook_torrance", **parse_params(args.param))
        scene.add(mesh, mat, xf)  # ambient: the material's white-sky albedo
        if not args.no_floor:
            _floor(scene, 0.0, 12.0)
        # The mesh now fills the unit sphere centred at (0, -lo, 0), its lowest point at y = 0.
        cam = Camera.framing(
            (0.0, -lo, 0.0), 1.0, (0.0, 0.45, 1.0), fovy=args.fovy, aspect=aspect, margin=1.08
        )
    else:
        gold = model("cook_torrance", metal="au", fresnel="conductor", roughness=0.28)
        scene.add(icosphere(5), gold, translate(-1.55, 0.62, 0.15) @ scale(0.62))
        red = model("blinn_phong", kd=(0.55, 0.05, 0.04), ks=0.35, shininess=90)
        scene.add(
            torus(96, 48),
            red,
            translate(1.55, 0.72, 0.1) @ rotate((0, 1, 0), -35) @ rotate((1, 0, 0), -20) @ scale(0.72),
        )
        clay = model("oren_nayar", kd=(0.60, 0.47, 0.34), sigma=0.35)
        cow = builtin_mesh("cow")
        lo = cow.bounds()[0][1]
        scene.add(
            cow,
            clay,
            translate(0.0, -lo * 1.9, -0.5) @ rotate((0, 1, 0), 35) @ scale(1.9),
        )
        if args.model is not None:
            mat = model(args.model, **parse_params(args.param))
            for inst in scene.instances:
                inst.material = mat  # its ambient follows: the white-sky albedo of the new material
        if not args.no_floor:
            _floor(scene, 0.0, 30.0)
        cam = Camera.perspective((0.0, 1.55, 4.6), (0.0, 0.5, 0.0), fovy=args.fovy)
    if args.light:
        for light in (parse_light(t) for t in args.light):
            scene.add_light(light)
    else:
        for light in _default_lights():
            scene.add_light(light)
    if args.eye is not None or args.target is not None:
        eye = _floats(args.eye, "--eye", 3) if args.eye is not None else cam.eye
        target = _floats(args.target, "--target", 3) if args.target is not None else cam.target
        cam = Camera.perspective(eye, target, fovy=args.fovy, near=0.05, far=200.0)
    return scene, cam


def _load_mesh_option(text: str) -> Mesh:
    """The mesh of ``--mesh PATH`` or ``--mesh builtin:NAME``; errors name ``--mesh`` (not the library's
    internal argument names ``path`` / ``name``) and what was given."""
    try:
        return builtin_mesh(text[8:]) if text.startswith("builtin:") else load_mesh(text, orient="keep")
    except (OSError, ValueError) as e:
        msg = str(e)
        for internal in ("path: ", "name: "):
            if msg.startswith(internal):
                msg = msg[len(internal) :]
        if isinstance(e, FileNotFoundError):
            msg = f"no such file: {text!r}"
        raise type(e)(f"--mesh: {msg}") from None


def canonical_scene(level: int = 5, material: Any = None) -> tuple[Scene, Camera]:
    """The canonical benchmark scene: ``icosphere(level)`` with the classic Blinn-Phong
    material (kd (0.8, 0.3, 0.2), ks 0.5, shininess 32, ambient 0.05·kd under white ambient light), a
    directional light travelling along (−1, −1, −1) and a point light of intensity 10 at (2, 2, 2) with
    inverse-square falloff, black background; camera at (0, 0, 3) looking at the origin, fovy 45°."""
    kd = (0.8, 0.3, 0.2)
    mat = material or model("blinn_phong_classic", kd=kd, ks=0.5, shininess=32)
    scene = Scene(ambient_light=1.0, background=0.0)
    scene.add(icosphere(level), mat, ambient=tuple(0.05 * c for c in kd))
    scene.add_light(DirectionalLight((-1.0, -1.0, -1.0), 1.0))
    scene.add_light(PointLight((2.0, 2.0, 2.0), 10.0, attenuation="inverse_square"))
    return scene, Camera.perspective((0.0, 0.0, 3.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0), 45.0, 0.1, 100.0)


# -- command line -------------------------------------------------------------------------------------------


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(p) for p in text.lower().replace("×", "x").split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT, e.g. 1280x720, got {text!r}") from None
    if w < 1 or h < 1:
        # Checked here, before the camera's aspect ratio width / height is formed.
        raise argparse.ArgumentTypeError(f"width and height must be at least 1 pixel each, got {text!r}")
    return w, h


def add_parser(sub: Any) -> argparse.ArgumentParser:
    """Add the ``render`` sub-command to ``sub`` (an argparse sub-parsers object)."""
    r: argparse.ArgumentParser = sub.add_parser(
        "render",
        help="render a 3D scene with the CPU rasterizer to a PNG (built-in scene, or --mesh PATH)",
        description=textwrap.fill(
            "Render a scene with brdfpy's tiled, multithreaded CPU rasterizer and write a PNG. "
            "Without --mesh: "
            "a built-in scene (a gold Cook-Torrance sphere, a red Blinn-Phong torus and Garland's cow in "
            "Oren-Nayar clay on a floor, three colored lights, shadows). With --mesh PATH: your OBJ or PLY "
            "file, scaled to a unit sphere, standing on the floor, in the chosen --model. --scene canonical "
            "renders the canonical benchmark scene and prints its check values.",
            width=78,
        )
        + "\n\n"
        + textwrap.fill(
            "Defaults: the command makes a presentation image (1280x720, 4 samples per pixel, shadows, ACES "
            "tone map; --scene canonical: 1920x1080, 1 sample, no shadows, clamp). Scene.render() in Python "
            "makes a reference render unless told otherwise (800x600, 1 sample, no shadows, clamp); "
            "scene.render(camera, 1280, 720, samples=4, shadows=True, tonemap='aces') gives this command's "
            "look.",
            width=78,
        ),
        epilog="Examples:\n"
        "  brdfpy render                                   # built-in scene -> brdfpy-render.png\n"
        "  brdfpy render --mesh bunny.ply --model cook_torrance --param roughness=0.2 --param metal=cu\n"
        "  brdfpy render --mesh builtin:fandisk --model blinn_phong_classic --shading gouraud\n"
        "  brdfpy render --light dir:-1,-1,-1:1,1,1 --light point:2,2,2:10,10,10 --size 1920x1080\n"
        "  brdfpy render --light from:1,1,1:2,2,2         # the light that travels along -1,-1,-1\n"
        "  brdfpy render --ao --no-shadows -o ao.png\n"
        "  brdfpy render --scene canonical --level 7 --samples 1 -o sphere.png\n"
        "  brdfpy render --mesh teapot.ply --up z --rotate 30\n"
        "  brdfpy render --scene helmet.glb --camera 1 -o helmet.png\n"
        "  brdfpy render --scene part.stl --up z --rotate 45\n\n"
        + textwrap.fill(
            f"Models: {', '.join(models())}. Built-in meshes: {', '.join(BUILTIN_MESHES)}.", width=78
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    r.add_argument(
        "-o",
        "--output",
        default="brdfpy-render.png",
        metavar="PATH",
        help="image file to write (default: brdfpy-render.png in the current folder)",
    )
    r.add_argument(
        "--scene",
        type=_scene_option,
        default="builtin",
        metavar="builtin|canonical|FILE",
        help="the built-in scene (default), the canonical benchmark scene, or a scene file: glTF 2.0 "
        "(.gltf with its .bin/images, .glb) with its materials, lights and cameras, OBJ with its MTL "
        "materials, STL or PLY, as brdfpy.load_scene reads it (textures are kept but not applied yet); "
        "rendered through the file's first camera (--camera N) or, without one, a camera framing it",
    )
    r.add_argument(
        "--camera",
        type=int,
        default=None,
        metavar="N",
        help="with --scene FILE: render through the file's camera N (0-based; default the first)",
    )
    r.add_argument(
        "--mesh",
        default=None,
        metavar="PATH",
        help="render this OBJ or PLY file (or builtin:NAME) instead of the built-in objects",
    )
    r.add_argument(
        "--model",
        default=None,
        metavar="NAME",
        help="reflectance model of the mesh (with --mesh; default cook_torrance) or of every object, "
        "with the model's defaults (brdfpy.model_info(NAME))",
    )
    r.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="change one parameter of --model from its default, e.g. roughness=0.2 or kd=0.8,0.3,0.2 "
        "(with --mesh and no --model: of cook_torrance, a red plastic); repeatable",
    )
    r.add_argument(
        "--shading",
        choices=SHADING_MODES,
        default="phong",
        help="where the reflectance model is evaluated: per face (flat), per vertex (gouraud) or per pixel "
        "(phong, quadratic; default phong); shadows are per pixel in every mode",
    )
    r.add_argument(
        "--light",
        action="append",
        default=None,
        metavar="SPEC",
        help=f"replace the default lights; repeatable. {LIGHT_SYNTAX}",
    )
    r.add_argument("--size", type=_size, default=None, metavar="WxH", help="image size (default 1280x720)")
    r.add_argument(
        "--samples",
        type=int,
        default=None,
        choices=(1, 4, 9, 16),
        help="supersampling per pixel (default 4; 1 for --scene canonical)",
    )
    r.add_argument(
        "--shadows",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="shadow rays toward every light (default on, off for --scene canonical)",
    )
    r.add_argument(
        "--ao", action="store_true", help="ambient obscurance (per vertex, 64 rays) on the ambient term"
    )
    r.add_argument(
        "--tonemap",
        choices=_tonemap.OPERATORS,
        default=None,
        help="tone-mapping operator (default aces; clamp for --scene canonical)",
    )
    r.add_argument("--exposure", type=float, default=0.0, metavar="EV", help="exposure in stops (default 0)")
    r.add_argument(
        "--fovy", type=float, default=40.0, metavar="DEG", help="vertical field of view (default 40)"
    )
    r.add_argument(
        "--eye", default=None, metavar="X,Y,Z", help="camera position (default: framed automatically)"
    )
    r.add_argument("--target", default=None, metavar="X,Y,Z", help="point the camera looks at")
    r.add_argument(
        "--up",
        choices=UP_AXES,
        default="y",
        type=lambda t: t.strip().lower().lstrip("+"),
        help="the mesh or scene file's up axis, turned to +y (z for CAD/3D-printing/Blender files; "
        "default y); with --scene FILE the framing camera is used unless --camera is given",
    )
    r.add_argument(
        "--rotate",
        action="append",
        default=[],
        metavar="[AXIS:]DEG",
        help="turn the mesh after --up: DEG about the vertical axis (180 shows its back), or "
        "x|y|z|X,Y,Z:DEG; repeatable, applied in order",
    )
    r.add_argument("--no-floor", action="store_true", help="leave out the floor")
    r.add_argument(
        "--flip",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="reverse the mesh's winding (default: when its signed volume is negative)",
    )
    r.add_argument(
        "--smooth",
        choices=("angle", "area", "equal"),
        default=None,
        help="recompute the mesh's vertex normals with this weighting",
    )
    r.add_argument("--level", type=int, default=5, help="icosphere level of --scene canonical (default 5)")
    r.add_argument(
        "--threads", type=int, default=None, metavar="N", help="worker threads (default: all cores)"
    )
    r.add_argument("-q", "--quiet", action="store_true", help="no progress bar or summary")
    return r


def run(args: argparse.Namespace) -> int:
    """Run ``brdfpy render`` with parsed options; returns the exit status."""
    from brdfpy import set_num_threads

    canonical = args.scene == "canonical" and args.mesh is None
    args.width, args.height = args.size or ((1920, 1080) if canonical else (1280, 720))
    samples = args.samples or (1 if canonical else 4)
    shadows = (not canonical) if args.shadows is None else args.shadows
    tonemap = args.tonemap or ("clamp" if canonical else "aces")
    if args.threads is not None:
        set_num_threads(args.threads)
    t0 = time.perf_counter()
    scene, cam = build_scene(args)
    t_build = time.perf_counter() - t0
    bar = None if args.quiet else ProgressBar("brdfpy render", delay=0.3)
    t1 = time.perf_counter()
    img = scene.render(
        cam,
        args.width,
        args.height,
        args.shading,
        samples=samples,
        tonemap=tonemap,
        exposure=args.exposure,
        ao=True if args.ao else None,
        shadows=shadows,
        progress=bar,
    )
    t_render = time.perf_counter() - t1
    img.save(args.output)
    if not args.quiet:
        asset = getattr(scene, "asset", None)
        for line in [] if asset is None else [*asset.skipped, *asset.notes]:
            print(f"{args.scene}: {line}")
        faces = sum(i.mesh.n_faces for i in scene.instances)
        print(
            f"wrote {args.output} ({img.width}x{img.height}, {faces:,} triangles, "
            f"{len(scene.lights)} lights, "
            f"{args.shading} shading, {samples} spp) — scene {t_build:.2f} s, render {t_render:.2f} s"
        )
        if canonical:
            _report_checks(img)
    return 0


def _report_checks(img: Any) -> None:
    """Print the canonical scene's check values next to the render's pixels."""
    h, w = img.shape
    centre = img.rgb[h // 2, w // 2].tolist()
    print(f"centre pixel {centre} (expected: [232, 151, 127]); {img.covered_pixels:,} pixels covered")
