"""The ``brdfpy`` command (also ``python -m brdfpy``).

Sub-commands:

``render`` (what a bare ``brdfpy`` runs)
    Render a 3D scene with the CPU rasterizer to a PNG (see :mod:`brdfpy.render_cmd`).

``gallery``
    Write a PNG contact sheet of lit spheres, one per reflectance model (see :mod:`brdfpy.gallery`).

``plot``, ``explore``
    Plot a model's BRDF Explorer views to a file; serve the interactive explorer (see
    :mod:`brdfpy.views_cli`).

``batch``
    Render a sweep spec on a Dask cluster into a folder (see :mod:`brdfpy.batch_cli`).
"""

from __future__ import annotations

import argparse
import re
import sys
import textwrap
import time
from collections.abc import Sequence
from typing import Any

from brdfpy import __version__, batch_cli, gallery, models, render_cmd, views, views_cli
from brdfpy.lights import DirectionalLight

__all__ = ["main"]

_COMMANDS = ("gallery", "render", "plot", "explore", "batch")


def _parse_params(items: Sequence[str]) -> dict[str, dict[str, Any]]:
    out: dict[str, dict[str, Any]] = {}
    for item in items:
        key, sep, value = item.partition("=")
        name, dot, param = key.strip().partition(".")
        if not sep or not dot or not name or not param:
            raise ValueError(
                f"--param: expected MODEL.KEY=VALUE (e.g. cook_torrance.roughness=0.1), got {item!r}"
            )
        out.setdefault(name, {})[param] = render_cmd.parse_value(value)
    return out


def _parse_light(text: str) -> DirectionalLight:
    """The gallery's ``--light``: ``dir:DX,DY,DZ`` (direction of travel) or ``from:X,Y,Z`` (toward the
    light), the spelling of ``brdfpy render --light``; R,G,B is refused by the gallery itself."""
    light = render_cmd.parse_light(text, kinds=("dir", "from"))
    assert isinstance(light, DirectionalLight)  # the only kinds asked for
    return light


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="brdfpy",
        description="brdfpy: fast reflectance models (BRDFs) with a Rust core. "
        "Without a sub-command, runs 'render' (the built-in scene) with its defaults.",
    )
    p.add_argument("--version", action="version", version=f"brdfpy {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    render_cmd.add_parser(sub)
    views_cli.add_plot_parser(sub)
    views_cli.add_explore_parser(sub)
    batch_cli.add_parser(sub)
    g = sub.add_parser(
        "gallery",
        help="write a PNG contact sheet of lit spheres, one per model",
        description=textwrap.fill(
            "Write a PNG contact sheet of lit spheres, one per reflectance model, with its name under it. "
            "Each sphere is shaded per pixel from its analytic normal (orthographic view along -z, viewer "
            "v = +z) by one directional light and a faint uniform sky. Physical models are lit with "
            "irradiance pi (a white Lambert sphere shows its albedo), classic course models by their "
            "formula as written; anisotropic models get tangents circling the vertical axis.",
            width=78,
        ),
        epilog="Examples:\n"
        "  brdfpy gallery -o spheres.png\n"
        "  brdfpy gallery --models lambert,cook_torrance,ward --size 256 --columns 3\n"
        "  brdfpy gallery --param cook_torrance.roughness=0.1 --param cook_torrance.metal=au\n"
        "  brdfpy gallery --light from:-1,1,0.5 --tonemap aces --exposure 1\n"
        "  brdfpy gallery --light dir:1,-1,-0.5        # the same light, by its direction of travel\n\n"
        + textwrap.fill(f"Models: {', '.join(models())}.", width=78),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    g.add_argument(
        "-o",
        "--output",
        default="brdfpy-gallery.png",
        metavar="PATH",
        help="PNG file to write (default: brdfpy-gallery.png in the current folder)",
    )
    g.add_argument(
        "--models",
        default=None,
        metavar="A,B,...",
        help="comma-separated model names to show, in this order (default: every model)",
    )
    g.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="MODEL.KEY=VALUE",
        help="set a model parameter, e.g. cook_torrance.roughness=0.1 or lambert.kd=0.8,0.2,0.2 "
        "(colors and arrays as comma-separated numbers, true/false for flags); repeatable",
    )
    g.add_argument(
        "--light",
        default="dir:-1,-1,-1",
        metavar="SPEC",
        help="the directional light, as in 'brdfpy render --light': dir:DX,DY,DZ is the direction in which "
        "it travels, from:X,Y,Z the direction toward it (need not be unit length; +x right, +y up, +z "
        "toward the viewer; default dir:-1,-1,-1, i.e. from:1,1,1: from the upper right, in front)",
    )
    g.add_argument(
        "--size", type=int, default=160, metavar="PIXELS", help="sphere diameter in pixels (default 160)"
    )
    g.add_argument(
        "--columns",
        type=int,
        default=None,
        metavar="N",
        help="spheres per row (default: about sqrt(count) + 1)",
    )
    g.add_argument(
        "--tonemap",
        default="auto",
        choices=views.SPHERE_TONEMAPS,
        help="how HDR values above 1 are mapped into [0, 1] before sRGB encoding (default auto: extended "
        "Reinhard with the white point at each sphere's peak, so highlights keep their fall-off)",
    )
    g.add_argument(
        "--exposure",
        type=float,
        default=0.0,
        metavar="EV",
        help="exposure in stops before tone mapping (default 0)",
    )
    g.add_argument(
        "--ambient",
        type=float,
        default=0.05,
        metavar="L",
        help="radiance of the uniform sky that lights the dark side (default 0.05; 0 turns it off)",
    )
    return p


def _gallery(args: argparse.Namespace) -> int:
    names = None if args.models is None else [s.strip() for s in args.models.split(",") if s.strip()]
    params = _parse_params(args.param)
    if names is None:
        names = list(models())
    t0 = time.perf_counter()
    w, h = gallery.save_gallery(
        args.output,
        names=names,
        params=params,
        light=_parse_light(args.light),
        size=args.size,
        columns=args.columns,
        tonemap_operator=args.tonemap,
        exposure=args.exposure,
        ambient=args.ambient,
    )
    dt = time.perf_counter() - t0
    print(f"wrote {args.output} ({w}x{h} pixels, {len(names)} models) in {dt:.2f} s")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``brdfpy`` command with ``argv`` (default: ``sys.argv[1:]``); returns the exit status."""
    args_in = list(sys.argv[1:] if argv is None else argv)
    # A bare `brdfpy`, or options without a sub-command, run the render.
    if not args_in or (args_in[0] not in _COMMANDS and args_in[0] not in ("-h", "--help", "--version")):
        args_in = ["render", *args_in]
    # "--light -1,1,0.5": argparse would take "-1,1,0.5" for an option; glue such values to their flag.
    glued: list[str] = []
    for a in args_in:
        flags = ("--light", "--exposure", "--ambient", "--theta-i", "--phi", *render_cmd.NEGATIVE_VALUE_FLAGS)
        negative_axis = glued and glued[-1] == "--up" and a.lower() in ("-x", "-y", "-z")
        if glued and (negative_axis or (glued[-1] in flags and re.match(r"^-[\d.]", a))):
            glued[-1] = f"{glued[-1]}={a}"
        else:
            glued.append(a)
    args_in = glued
    parser = _parser()
    args = parser.parse_args(args_in)
    run = {
        "render": render_cmd.run,
        "plot": views_cli.run_plot,
        "explore": views_cli.run_explore,
        "batch": batch_cli.run,
    }
    try:
        return run.get(args.command, _gallery)(args)
    except ImportError as e:
        print(f"brdfpy {args.command}: error: {e}", file=sys.stderr)
        return 2
    except (ValueError, TypeError, OSError) as e:
        print(f"brdfpy {args.command}: error: {e}", file=sys.stderr)
        return 2
