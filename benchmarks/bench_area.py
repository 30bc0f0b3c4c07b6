"""Area lights: the time to render 640×480 with a sphere light and with a rectangle light at a few
``area_samples``, and the RMSE of each against a high-sample reference.

Scene: ``icosphere(5)`` (20k triangles, Cook-Torrance copper, GGX α 0.3) resting on a white Lambert floor
(``plane(6, 8)``), camera at (0, 1.6, 3.2) looking at (0, 0.4, 0), lit by one area light: a sphere light
(centre (1, 2.2, 1), radius 0.4, radiance 25) or a rectangle light (1.2 × 0.8 at height 2.4, radiance 12).
For each light, ``area_samples`` = 1, 4, 16, 64 (one light and one material sample each, MIS) and a
reference at 1024 (256 with ``--quick``, another seed); RMSE over the covered pixels of the HDR image, and
relative to their mean. Median of ``--repeat`` renders per count.

Run through ``python benchmarks/run.py area`` or directly; ``--quick`` checks that it runs.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np


def bench(size: tuple[int, int], reference: int, counts: list[int], repeat: int) -> dict[str, Any]:
    import brdfpy

    load_before = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    w, h = size
    cam = brdfpy.Camera.perspective(eye=(0, 1.6, 3.2), target=(0, 0.4, 0), fovy=45)
    lights = {
        "sphere": brdfpy.SphereLight((1.0, 2.2, 1.0), 0.4, 25.0),
        "rect": brdfpy.RectLight((-0.5, 2.4, 0.3), (1.2, 0, 0), (0, 0, 0.8), 12.0),
    }
    out: dict[str, Any] = {}
    for name, light in lights.items():
        scene = brdfpy.Scene()
        scene.add(brdfpy.plane(6.0, 8), brdfpy.model("lambert", kd=1.0))
        cu = brdfpy.model("cook_torrance", roughness=0.3, metal="cu")
        scene.add(
            brdfpy.icosphere(5), cu, brdfpy.transforms.translate(0, 0.5, 0) @ brdfpy.transforms.scale(0.5)
        )
        scene.add_light(light)

        def render(
            n: int, seed: int = 0, scene: brdfpy.Scene = scene
        ) -> tuple[np.ndarray, np.ndarray, float]:
            t0 = time.perf_counter()
            img = scene.render(cam, w, h, area_samples=n, area_seed=seed, outputs=("hdr", "triangle_id"))
            return img.hdr, img.triangle_id >= 0, time.perf_counter() - t0

        ref, mask, ref_t = render(reference, seed=12345)
        rows = []
        for n in counts:
            times = []
            for _ in range(repeat):
                img, _, t = render(n)
                times.append(t)
            rmse = float(np.sqrt(np.mean((img[mask] - ref[mask]) ** 2)))
            assert np.isfinite(img).all()
            rows.append(
                {
                    "area_samples": n,
                    "seconds": statistics.median(times),
                    "rmse": rmse,
                    "relative_rmse": rmse / float(ref[mask].mean()),
                }
            )
        out[name] = {"reference_samples": reference, "reference_seconds": ref_t, "rows": rows}
    return {
        "machine": {
            "platform": platform.platform(),
            "cpus": os.cpu_count(),
            "threads": brdfpy.get_num_threads(),
            "brdfpy": brdfpy.__version__,
            "loadavg_before": load_before,
            "loadavg_after": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        },
        "size": f"{w}x{h}",
        "lights": out,
    }


def main(argv: Sequence[str] | None = None) -> dict[str, Any]:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--size", default="640x480", help="image size (default 640x480)")
    p.add_argument("--reference", type=int, default=1024, help="samples of the reference (default 1024)")
    p.add_argument("--counts", default="1,4,16,64", help="area_samples to time (default 1,4,16,64)")
    p.add_argument("--repeat", type=int, default=3, help="renders per count, median time (default 3)")
    p.add_argument("--quick", action="store_true", help="tiny sizes: checks that the benchmark runs")
    p.add_argument("--json", default=None, help="also write the results to this file")
    a = p.parse_args(argv)
    w, h = (int(x) for x in a.size.lower().split("x"))
    if a.quick:
        w, h, a.reference, a.counts, a.repeat = 160, 120, 256, "1,4", 1
    result = bench((w, h), a.reference, [int(x) for x in a.counts.split(",")], a.repeat)
    for name, r in result["lights"].items():
        print(
            f"{name} light, {result['size']}, reference {r['reference_samples']} spp "
            f"({r['reference_seconds']:.2f} s)"
        )
        for row in r["rows"]:
            print(
                f"  area_samples {row['area_samples']:5d}  {row['seconds']:7.3f} s  RMSE {row['rmse']:.4f} "
                f"({100 * row['relative_rmse']:.1f} % of the mean)"
            )
    if a.json:
        Path(a.json).write_text(json.dumps(result, indent=2) + "\n")
    return result


if __name__ == "__main__":
    main()
