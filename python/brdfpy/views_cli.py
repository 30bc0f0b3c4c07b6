"""The ``brdfpy plot`` and ``brdfpy explore`` sub-commands (registered by :mod:`brdfpy.cli`).

Building their parsers imports neither matplotlib nor Panel, so ``brdfpy --help`` works without the optional
extras; running them imports the extra and says which one to install when it is missing.
"""

from __future__ import annotations

import argparse
import os
import textwrap
import time
from typing import Any

from brdfpy import models
from brdfpy.models import Model
from brdfpy.render_cmd import parse_value

__all__ = ["add_explore_parser", "add_plot_parser", "load_models", "run_explore", "run_plot"]

PLOT_VIEWS = ("polar", "lobe", "slice", "albedo", "sphere", "all")


def load_models(spec: str, params: list[str]) -> list[Model]:
    """Models from ``a,b,...`` (registry names, or paths of MERL ``.binary`` files) and ``--param`` items
    ``KEY=VALUE`` (for every model) or ``MODEL.KEY=VALUE`` (for one)."""
    from brdfpy.measured import Tabulated

    names = [s.strip() for s in spec.split(",") if s.strip()]
    if not names:
        raise ValueError("MODEL: expected a model name (or several, comma-separated)")
    shared: dict[str, Any] = {}
    per: dict[str, dict[str, Any]] = {}
    for item in params:
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise ValueError(f"--param: expected KEY=VALUE or MODEL.KEY=VALUE, got {item!r}")
        model_name, dot, param = key.partition(".")
        if dot and model_name in names:
            per.setdefault(model_name, {})[param] = parse_value(value)
        else:
            shared[key] = parse_value(value)
    out: list[Model] = []
    for name in names:
        if name.endswith(".binary") or os.sep in name or os.path.exists(name):
            if per.get(name) or shared:
                raise ValueError(f"--param: a measured table ({name}) has no parameters")
            out.append(Tabulated.load_merl(name).as_model())
        else:
            out.append(Model(name, **{**shared, **per.get(name, {})}))
    return out


def add_plot_parser(sub: Any) -> argparse.ArgumentParser:
    """Add ``brdfpy plot`` to ``sub`` (an argparse sub-parsers object)."""
    p: argparse.ArgumentParser = sub.add_parser(
        "plot",
        help="plot a model's BRDF Explorer views (polar, lobe, slice, albedo, sphere) to a PNG or SVG",
        description=textwrap.fill(
            "Plot the views of BRDF Explorer for one model, or several overlaid (comma-separated): the "
            "in-plane polar slice, the 3D lobe, the theta_h/theta_d image slice, the directional albedo "
            "curve, the lit sphere, or all of them. Needs the optional extra brdfpy[plot] (matplotlib).",
            width=78,
        ),
        epilog="Examples:\n"
        "  brdfpy plot cook_torrance --view polar --theta-i 30 -o polar.png\n"
        "  brdfpy plot cook_torrance,blinn_phong --param cook_torrance.roughness=0.2 --view all -o all.svg\n"
        "  brdfpy plot blue-metallic-paint.binary --view slice -o slice.png\n\n"
        + textwrap.fill(f"Models: {', '.join(models())}.", width=78),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("model", metavar="MODEL", help="model name(s), comma-separated, or a MERL .binary file")
    p.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="[MODEL.]KEY=VALUE",
        help="set a parameter (of every model, or of MODEL), e.g. roughness=0.1; repeatable",
    )
    p.add_argument("--view", default="all", choices=PLOT_VIEWS, help="which view (default all: a dashboard)")
    p.add_argument(
        "--theta-i", type=float, default=45.0, metavar="DEG", help="incidence angle in [0, 90] (default 45)"
    )
    p.add_argument(
        "--phi", type=float, default=0.0, metavar="DEG", help="azimuth of the plane of incidence (default 0)"
    )
    p.add_argument("--log", action="store_true", help="logarithmic radius for the polar plot")
    p.add_argument("--cosine", action="store_true", help="polar plot of f_r cos(theta_o) instead of f_r")
    p.add_argument(
        "-o",
        "--output",
        default="brdfpy-plot.png",
        metavar="PATH",
        help="PNG or SVG file (default brdfpy-plot.png)",
    )
    p.add_argument("--dpi", type=int, default=110, help="resolution of a PNG (default 110)")
    return p


def run_plot(args: argparse.Namespace) -> int:
    ext = os.path.splitext(args.output)[1].lower()
    if ext not in (".png", ".svg"):
        raise ValueError(f"--output: expected a .png or .svg file, got {args.output!r}")
    ms = load_models(args.model, args.param)
    import matplotlib

    matplotlib.use("Agg")
    from brdfpy import plot

    t0 = time.perf_counter()
    fig: Any
    if args.view == "all":
        fig = plot.dashboard(ms, args.theta_i, phi=args.phi)
    elif args.view == "polar":
        fig = plot.polar(ms, args.theta_i, phi=args.phi, log=args.log, cosine=args.cosine).figure
    elif args.view == "lobe":
        fig = plot.lobe(ms, args.theta_i, phi=args.phi).figure
    elif args.view == "slice":
        import matplotlib.pyplot as plt

        f = plt.figure(figsize=(5.0 * len(ms), 4.2), layout="constrained")
        for k, m in enumerate(ms):
            plot.half_diff_slice(m, ax=f.add_subplot(1, len(ms), k + 1))
        fig = f
    elif args.view == "albedo":
        fig = plot.albedo(ms).figure
    else:
        fig = plot.lit_sphere(ms, theta_i=args.theta_i, phi=args.phi)[0].figure
    fig.savefig(args.output, dpi=args.dpi)
    dt = time.perf_counter() - t0
    print(f"wrote {args.output} ({args.view}, {', '.join(m.name for m in ms)}) in {dt:.2f} s")
    return 0


def add_explore_parser(sub: Any) -> argparse.ArgumentParser:
    """Add ``brdfpy explore`` to ``sub``."""
    p: argparse.ArgumentParser = sub.add_parser(
        "explore",
        help="open the interactive BRDF explorer in the browser (served on 127.0.0.1 only)",
        description=textwrap.fill(
            "Serve the BRDF explorer, a page with the model's parameters as controls and its views live "
            "(lit sphere, polar slice, lobe, theta_h/theta_d slice, albedo, a lit object), on "
            "http://127.0.0.1:PORT, and open it in the browser. Ctrl-C stops it. Needs the optional extra "
            "brdfpy[explore] (Panel).",
            width=78,
        ),
        epilog="Examples:\n  brdfpy explore\n  brdfpy explore cook_torrance,ward --port 5007 --no-browser\n",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "model", metavar="MODEL", nargs="?", default="cook_torrance", help="first model(s), comma-separated"
    )
    p.add_argument(
        "--param", action="append", default=[], metavar="[MODEL.]KEY=VALUE", help="initial parameter"
    )
    p.add_argument("--port", type=int, default=0, help="port on 127.0.0.1 (default: a free one)")
    p.add_argument("--no-browser", action="store_true", help="do not open a browser")
    return p


def run_explore(args: argparse.Namespace) -> int:
    if not 0 <= args.port <= 65535:
        raise ValueError(f"--port: expected 0 to 65535, got {args.port}")
    ms = load_models(args.model, args.param)
    from brdfpy import explorer

    explorer.serve(ms, port=args.port, show=not args.no_browser)
    return 0
