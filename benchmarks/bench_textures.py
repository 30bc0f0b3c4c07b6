"""Textures: the frame time of a textured scene against the same scene untextured, at 1920×1080.

Scene: a UV sphere (128 rings × 256 segments, 66k triangles, texture coordinates glTF-style) filling most
of the frame, Cook-Torrance (GGX, height-correlated Smith, Schlick F0 0.04), one directional light and a
faint ambient light, Phong shading. Textured: ``kd`` from a 1024² RGB texture (a wood-like procedural
pattern, sRGB 8-bit) and ``roughness`` from the green channel of a 1024² RGB texture, both trilinear
(mip-mapped); untextured: the same mesh and model with the textures' means as constants. Median of
``--frames`` renders after one warm-up, at 1 and 2 threads (``--threads``), interleaved; the ratio is
textured over untextured, the target of issue 12 is ≤ 1.3. The load average is recorded: the machine may
be shared.

Run through ``python benchmarks/run.py textures`` or directly; ``--quick`` checks that it runs.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time
from collections.abc import Sequence
from typing import Any

import numpy as np


def uv_sphere(rings: int, segments: int) -> Any:
    import brdfpy

    th = np.linspace(0, np.pi, rings + 1)
    ph = np.linspace(0, 2 * np.pi, segments + 1)
    t, p = np.meshgrid(th, ph, indexing="ij")
    pos = np.stack([np.sin(t) * np.cos(p), np.cos(t), -np.sin(t) * np.sin(p)], -1).reshape(-1, 3)
    uv = np.stack([p / (2 * np.pi) * 4, t / np.pi * 2], -1).reshape(-1, 2)  # the textures repeat 4 × 2
    k = np.arange(rings * (segments + 1)).reshape(rings, segments + 1)[:, :-1].ravel()
    a, b, c, d = k, k + 1, k + segments + 1, k + segments + 2
    faces = np.concatenate([np.stack([a, c, b], 1), np.stack([b, c, d], 1)])
    return brdfpy.Mesh(pos, faces, pos, uvs=uv)


def textures(n: int) -> tuple[np.ndarray, np.ndarray]:
    y, x = np.mgrid[0:n, 0:n] / n
    rings = 0.5 + 0.5 * np.sin(40 * np.hypot(x - 0.3, y - 0.6) + 6 * np.sin(9 * x))
    wood = np.stack([0.45 + 0.35 * rings, 0.25 + 0.2 * rings, 0.1 + 0.08 * rings], -1)
    kd = np.round(255 * np.clip(wood, 0, 1) ** (1 / 2.2)).astype(np.uint8)
    mr = np.zeros((n, n, 3), np.uint8)
    mr[..., 1] = np.round(255 * (0.2 + 0.5 * rings)).astype(np.uint8)
    return kd, mr


def main(argv: Sequence[str] | None = None) -> dict[str, Any]:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--frames", type=int, default=5)
    p.add_argument("--threads", default="1,2")
    p.add_argument("--size", default="1920x1080")
    p.add_argument("--texture", type=int, default=1024)
    p.add_argument("--quick", action="store_true")
    args = p.parse_args(list(argv) if argv is not None else None)
    import brdfpy

    w, h = (int(s) for s in args.size.split("x"))
    n, frames, rings = args.texture, args.frames, 128
    if args.quick:
        w, h, n, frames, rings = 320, 180, 64, 1, 16
    kd8, mr8 = textures(n)
    kd_tex = brdfpy.Texture(kd8, filter="trilinear")
    mr_tex = brdfpy.Texture(mr8, filter="trilinear", colorspace="linear")
    textured = brdfpy.model("cook_torrance", kd=kd_tex, roughness=mr_tex.channel(1), f0=0.04)
    plain = brdfpy.model("cook_torrance", **textured.params)
    mesh = uv_sphere(rings, 2 * rings)
    cam = brdfpy.Camera.perspective(eye=(0, 0.3, 2.6), target=(0, 0, 0), fovy=45)
    scenes = {}
    for name, model in (("untextured", plain), ("textured", textured)):
        s = brdfpy.Scene(ambient_light=0.05)
        s.add(mesh, model)
        s.add_light(brdfpy.DirectionalLight(direction=(-1, -1, -1), color=3.0))
        scenes[name] = s
    rows = []
    before = brdfpy.get_num_threads()
    try:
        for threads in (int(t) for t in args.threads.split(",")):
            brdfpy.set_num_threads(threads)
            times: dict[str, list[float]] = {k: [] for k in scenes}
            for s in scenes.values():
                s.render(cam, w, h)  # warm-up
            for _ in range(frames):
                for k, s in scenes.items():
                    t0 = time.perf_counter()
                    s.render(cam, w, h)
                    times[k].append(time.perf_counter() - t0)
            med = {k: statistics.median(v) for k, v in times.items()}
            row = {
                "threads": threads,
                "untextured_ms": 1e3 * med["untextured"],
                "textured_ms": 1e3 * med["textured"],
                "ratio": med["textured"] / med["untextured"],
                "load_average": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
            }
            rows.append(row)
            print(
                f"{threads} thread(s): untextured {row['untextured_ms']:.1f} ms, textured "
                f"{row['textured_ms']:.1f} ms, ratio {row['ratio']:.2f} (target ≤ 1.30; "
                f"load {row['load_average']})",
                flush=True,
            )
    finally:
        brdfpy.set_num_threads(before)
    return {
        "benchmark": "textures",
        "size": [w, h],
        "texture": n,
        "triangles": mesh.n_faces,
        "frames": frames,
        "rows": rows,
        "machine": platform.machine(),
        "cpus": os.cpu_count(),
    }


if __name__ == "__main__":
    main()
