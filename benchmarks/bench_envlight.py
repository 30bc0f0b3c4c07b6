"""Environment lighting: the fast mode's frame time against the plain renderer's, and the Monte Carlo mode's
time to a noise level.

- fast mode: ``icosphere(7)`` (330k triangles) with a Cook-Torrance copper material (GGX, α 0.25) at
  1920×1080, lit by the procedural sky (``Environment.sky()``) in the fast mode, against the same scene lit
  by one directional light and no environment (the plain renderer); median of ``--frames`` frames after
  one untimed frame (which prefilters the map once). The first frame's time is reported too.
- Monte Carlo: a glossy sphere (Cook-Torrance, GGX α 0.2, copper) in the sky at 256×256, rendered with
  ``env_samples`` = 4, 16, 64, ...; the RMSE of the lit pixels against a 4096-sample reference (1024 with
  ``--quick``) and the time of each render, so the time to a given noise level can be read off.

Run through ``python benchmarks/run.py envlight`` or directly; ``--quick`` checks that it runs.
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


def _frame_times(render: Any, frames: int) -> tuple[float, float]:
    t0 = time.perf_counter()
    render()
    first = time.perf_counter() - t0
    times = []
    for _ in range(frames):
        t0 = time.perf_counter()
        render()
        times.append(time.perf_counter() - t0)
    return first, statistics.median(times)


def bench(
    size: tuple[int, int], level: int, frames: int, mc_size: int, reference: int, counts: list[int]
) -> dict[str, Any]:
    import brdfpy

    load_before = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    w, h = size
    cu = brdfpy.model("cook_torrance", roughness=0.25, metal="cu")
    cam = brdfpy.Camera.perspective(eye=(0, 0, 3), target=(0, 0, 0), fovy=45)
    sky = brdfpy.Environment.sky()

    plain = brdfpy.Scene()
    plain.add(brdfpy.icosphere(level), cu)
    plain.add_light(brdfpy.DirectionalLight(direction=(-1, -1, -1), color=3.0))
    lit = brdfpy.Scene(environment=sky)
    lit.add(brdfpy.icosphere(level), cu)
    plain_first, plain_t = _frame_times(lambda: plain.render(cam, w, h).rgb, frames)
    fast_first, fast_t = _frame_times(lambda: lit.render(cam, w, h).rgb, frames)

    glossy = brdfpy.Scene(environment=sky)
    glossy.add(brdfpy.icosphere(6), brdfpy.model("cook_torrance", roughness=0.2, metal="cu"))

    def mc(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray, float]:
        t0 = time.perf_counter()
        img = glossy.render(
            cam,
            mc_size,
            mc_size,
            env_mode="monte_carlo",
            env_samples=n,
            env_seed=seed,
            outputs=("hdr", "triangle_id"),
        )
        return img.hdr, img.triangle_id >= 0, time.perf_counter() - t0

    ref, mask, ref_t = mc(reference, seed=12345)
    rows = []
    for n in counts:
        img, _, t = mc(n)
        rmse = float(np.sqrt(np.mean((img[mask] - ref[mask]) ** 2)))
        rows.append(
            {"env_samples": n, "seconds": t, "rmse": rmse, "relative_rmse": rmse / float(ref[mask].mean())}
        )
    fast_img = glossy.render(cam, mc_size, mc_size, outputs=("hdr",)).hdr
    fast_rmse = float(np.sqrt(np.mean((fast_img[mask] - ref[mask]) ** 2)))
    return {
        "machine": {
            "platform": platform.platform(),
            "cpus": os.cpu_count(),
            "threads": brdfpy.get_num_threads(),
            "brdfpy": brdfpy.__version__,
            "loadavg_before": load_before,
            "loadavg_after": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        },
        "fast": {
            "size": f"{w}x{h}",
            "triangles": brdfpy.icosphere(level).n_faces,
            "plain_seconds": plain_t,
            "fast_seconds": fast_t,
            "ratio": fast_t / plain_t,
            "plain_first_seconds": plain_first,
            "fast_first_seconds": fast_first,
        },
        "monte_carlo": {
            "size": f"{mc_size}x{mc_size}",
            "reference_samples": reference,
            "reference_seconds": ref_t,
            "rows": rows,
            "fast_mode_rmse_vs_reference": fast_rmse,
            "fast_mode_relative_rmse": fast_rmse / float(ref[mask].mean()),
        },
    }


def main(argv: Sequence[str] | None = None) -> dict[str, Any]:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--frames", type=int, default=5, help="timed frames of the fast mode (default 5)")
    p.add_argument("--size", default="1920x1080", help="fast-mode image size (default 1920x1080)")
    p.add_argument("--level", type=int, default=7, help="icosphere level of the fast-mode scene (default 7)")
    p.add_argument("--mc-size", type=int, default=256, help="Monte Carlo image side (default 256)")
    p.add_argument("--reference", type=int, default=4096, help="samples of the reference (default 4096)")
    p.add_argument("--counts", default="4,16,64,256", help="Monte Carlo sample counts (default 4,16,64,256)")
    p.add_argument("--quick", action="store_true", help="tiny sizes: checks that the benchmark runs")
    p.add_argument("--json", default=None, help="also write the results to this file")
    a = p.parse_args(argv)
    w, h = (int(x) for x in a.size.lower().split("x"))
    if a.quick:
        w, h, a.level, a.frames, a.mc_size, a.reference, a.counts = 192, 108, 4, 1, 32, 256, "4,16"
    result = bench((w, h), a.level, a.frames, a.mc_size, a.reference, [int(x) for x in a.counts.split(",")])
    if a.json:
        Path(a.json).write_text(json.dumps(result, indent=2) + "\n")
    return result


if __name__ == "__main__":
    print(json.dumps(main(), indent=2))
