"""Ray casting and ambient obscurance speed (issue 4): BVH build time, closest-hit and any-hit rays per
second, and per-vertex obscurance time at 64 rays per vertex, at 1 and 2 threads, through the Python API.

Meshes: the largest mesh of ``shared/assets/meshes`` (Newell's teapot, 515k triangles) and the ~100k-triangle
Cyberware horse (wound inward in the file, flipped here so that its normals point out); without
``../shared``, icosphere(7) and icosphere(6) (327k and 82k triangles) stand in.

Rays are what obscurance and shadows cast: from random points on the surface (uniform by area), offset by
1e-4 of the mesh's diagonal along the face normal, in cosine-distributed directions about it. Three queries:
closest hit over ``[0, inf)``, any hit over ``[0, inf)`` and any hit over ``[0, d_max]`` (an obscurance ray;
``d_max`` a quarter of the diagonal). Times are wall-clock of the ``RayCaster`` call, conversions included,
ray generation excluded; each configuration is run ``--repeat`` times, interleaving the thread counts, and the
best time is reported (the least disturbed by other processes; the median is in the JSON too), with the
process CPU time of that run (CPU/wall near the thread count means the threads really ran in parallel).

Baseline: a vectorised float64 NumPy Moller-Trumbore test of every ray against every triangle, on a small
subset of the rays (``--baseline-rays``), scaled to rays per second. The machine may be shared: the 1-minute
load average and the CPU pressure (Linux PSI: share of time some task waited for a CPU) before and after are
recorded; the 2-thread speed-up means little when the load exceeds the cores.

Run through ``python benchmarks/run.py ao`` or directly (``python benchmarks/bench_ao.py``).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

HERE = Path(__file__).resolve().parent
ASSETS = HERE.parent.parent / "shared" / "assets" / "meshes"
LARGEST = "newell_teapot_n96.ply"
HORSE = "cyberware_horse.ply"


def loadavg() -> float | None:
    return os.getloadavg()[0] if hasattr(os, "getloadavg") else None


def cpu_pressure() -> float | None:
    """Linux PSI: % of the last 10 s in which some runnable task waited for a CPU (None elsewhere)."""
    try:
        line = Path("/proc/pressure/cpu").read_text().splitlines()[0]
        return float(line.split("avg10=")[1].split()[0])
    except (OSError, IndexError, ValueError):
        return None


def load(spec: str) -> tuple[Any, str]:
    """``icosphere:L`` or a path; meshes wound inward (negative signed volume) are flipped."""
    import brdfpy

    if spec.startswith("icosphere:"):
        level = int(spec.split(":")[1])
        return brdfpy.icosphere(level), f"icosphere({level})"
    mesh = brdfpy.load_mesh(spec)
    if mesh.stats()["signed_volume"] < 0:
        mesh.flip_winding()
    return mesh, Path(spec).stem


def surface_rays(mesh: Any, n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, float]:
    """``n`` rays from random surface points (uniform by area), cosine-distributed about the face normal,
    offset along it by 1e-4 of the diagonal; returns origins, unit directions and the diagonal."""
    v = mesh.vertices.astype(np.float64)
    f = mesh.faces.astype(np.int64)
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    cross = np.cross(b - a, c - a)
    area = np.linalg.norm(cross, axis=1)
    ok = area > 0
    idx = np.flatnonzero(ok)[rng.choice(int(ok.sum()), n, p=area[ok] / area[ok].sum())]
    nrm = cross[idx] / area[idx, None]
    r1, r2 = rng.random(n), rng.random(n)
    s = np.sqrt(r1)
    p = (1 - s)[:, None] * a[idx] + (s * (1 - r2))[:, None] * b[idx] + (s * r2)[:, None] * c[idx]
    # Cosine-weighted direction in the frame of the normal (Duff et al. 2017 basis).
    u1, u2 = rng.random(n), rng.random(n)
    r, phi = np.sqrt(u1), 2 * np.pi * u2
    sign = np.where(nrm[:, 2] >= 0, 1.0, -1.0)
    aa = -1.0 / (sign + nrm[:, 2])
    bb = nrm[:, 0] * nrm[:, 1] * aa
    t = np.stack([1 + sign * nrm[:, 0] ** 2 * aa, sign * bb, -sign * nrm[:, 0]], axis=1)
    bt = np.stack([bb, sign + nrm[:, 1] ** 2 * aa, -nrm[:, 1]], axis=1)
    d = (r * np.cos(phi))[:, None] * t + (r * np.sin(phi))[:, None] * bt + np.sqrt(1 - u1)[:, None] * nrm
    lo, hi = mesh.bounds()
    diag = float(np.linalg.norm(hi - lo))
    o = p + 1e-4 * diag * nrm
    return o.astype(np.float32), d.astype(np.float32), diag


def brute_force_rays_per_second(mesh: Any, o: np.ndarray, d: np.ndarray, any_hit: bool) -> float:
    """Rays per second of a float64 NumPy Moller-Trumbore loop over every triangle (chunked by triangles)."""
    v = mesh.vertices.astype(np.float64)
    f = mesh.faces.astype(np.int64)
    a, e1, e2 = v[f[:, 0]], v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]
    o64, d64 = o.astype(np.float64), d.astype(np.float64)
    t0 = time.perf_counter()
    for k in range(len(o64)):
        dd, oo = d64[k], o64[k]
        p = np.cross(dd, e2)
        det = np.einsum("ij,ij->i", e1, p)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            s = oo - a
            u = np.einsum("ij,ij->i", s, p) * inv
            q = np.cross(s, e1)
            w = (q @ dd) * inv
            t = np.einsum("ij,ij->i", e2, q) * inv
        hit = (u >= 0) & (w >= 0) & (u + w <= 1) & (t > 0)
        if any_hit:
            bool(hit.any())
        else:
            float(np.min(np.where(hit, t, np.inf)))
    return len(o64) / (time.perf_counter() - t0)


def timed(fn: Callable[[], Any]) -> tuple[float, float]:
    c0, t0 = time.process_time(), time.perf_counter()
    fn()
    return time.perf_counter() - t0, time.process_time() - c0


def bench_mesh(
    mesh: Any,
    name: str,
    threads: list[int],
    n_rays: int,
    repeat: int,
    spv: int,
    n_base: int,
    rng: np.random.Generator,
) -> dict[str, Any]:
    """Time the build, the three queries and per-vertex obscurance on one mesh; print a table."""
    import brdfpy

    o, d, diag = surface_rays(mesh, n_rays, rng)
    d_max = 0.25 * diag
    print(f"\n{name}: {mesh.n_faces} triangles, {mesh.n_vertices} vertices, d_max {d_max:.4g}")
    entry: dict[str, Any] = {
        "mesh": name,
        "triangles": mesh.n_faces,
        "vertices": mesh.n_vertices,
        "d_max": d_max,
        "rows": {},
    }
    queries: dict[str, Callable[[Any], Any]] = {
        "closest_hit": lambda rc: rc.closest_hit(o, d),
        "any_hit": lambda rc: rc.any_hit(o, d),
        "any_hit_dmax": lambda rc: rc.any_hit(o, d, t_max=d_max),
    }
    samples: dict[tuple[str, int], list[tuple[float, float]]] = {}
    casters: dict[int, Any] = {}
    for _ in range(repeat):
        for n in threads:
            brdfpy.set_num_threads(n)
            c0 = time.process_time()
            casters[n] = brdfpy.RayCaster(mesh)
            samples.setdefault(("build", n), []).append((casters[n].build_seconds, time.process_time() - c0))
            for q, fn in queries.items():
                samples.setdefault((q, n), []).append(timed(lambda fn=fn, rc=casters[n]: fn(rc)))
    rc = casters[threads[0]]
    hit_rate = float(rc.closest_hit(o, d).hit.mean())
    entry["hit_rate_closest"] = hit_rate
    entry["hit_rate_dmax"] = float(rc.any_hit(o, d, t_max=d_max).mean())
    entry["bvh"] = rc.stats()
    # Obscurance is long on big meshes: one run per thread count.
    for n in threads:
        brdfpy.set_num_threads(n)
        samples[("obscurance", n)] = [timed(lambda: mesh.compute_obscurance(d_max=d_max, samples=spv))]
    base = {
        "closest_hit": brute_force_rays_per_second(mesh, o[:n_base], d[:n_base], any_hit=False),
        "any_hit": brute_force_rays_per_second(mesh, o[:n_base], d[:n_base], any_hit=True),
    }
    base["any_hit_dmax"] = base["any_hit"]  # brute force tests every triangle whatever t_max
    entry["numpy_bruteforce_rays_per_s"] = base

    cols = f"{'best s':>10}{'median s':>10}{'cpu/wall':>9}{'Mrays/s':>9}{'M/cpu-s':>9}{'x numpy':>10}"
    print(f"  {'query':<16}{'thr':>4}{cols}{'2T/1T':>7}")
    for q in ["build", *queries, "obscurance"]:
        for n in threads:
            runs = samples[(q, n)]
            best_wall, best_cpu = min(runs)
            row: dict[str, Any] = {
                "threads": n,
                "best_s": best_wall,
                "median_s": statistics.median(w for w, _ in runs),
                "cpu_s": best_cpu,
            }
            count = n_rays if q in queries else mesh.n_vertices * spv
            rate = per_cpu = numpy_x = speedup = ""
            if q != "build":
                row["rays_per_s"] = count / best_wall
                # Rays per second of CPU time used by the process: what the code costs, whatever share of
                # the cores other processes left it (an estimate: contention also slows each CPU second).
                row["rays_per_cpu_s"] = count / best_cpu
                rate = f"{row['rays_per_s'] / 1e6:.2f}"
                per_cpu = f"{row['rays_per_cpu_s'] / 1e6:.2f}"
                if q in base:
                    row["x_numpy"] = row["rays_per_s"] / base[q]
                    numpy_x = f"{row['x_numpy']:.0f}"
            one = samples.get((q, 1))
            if n != 1 and one:
                row["speedup_vs_1"] = min(one)[0] / best_wall
                speedup = f"{row['speedup_vs_1']:.2f}"
            entry["rows"].setdefault(q, []).append(row)
            cpu_wall = best_cpu / best_wall
            print(
                f"  {q:<16}{n:>4}{best_wall:>10.4f}{row['median_s']:>10.4f}{cpu_wall:>9.2f}"
                f"{rate:>9}{per_cpu:>9}{numpy_x:>10}{speedup:>7}"
            )
    print(
        f"  hit rate {hit_rate:.3f} (closest, unbounded), {entry['hit_rate_dmax']:.3f} (within d_max); "
        f"NumPy brute force (float64, {n_base} rays): {base['closest_hit']:.0f} / {base['any_hit']:.0f} "
        "rays/s (closest / any)"
    )
    return entry


def main(argv: list[str] | None = None) -> dict[str, Any]:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--quick", action="store_true", help="small meshes and batches: checks that it runs")
    p.add_argument("--rays", type=int, default=1_000_000, help="rays per query batch (default 1e6)")
    p.add_argument("--repeat", type=int, default=3, help="timed runs per configuration (default 3)")
    p.add_argument("--threads", default="1,2", help="thread counts (default 1,2)")
    p.add_argument("--samples", type=int, default=64, help="obscurance rays per vertex (default 64)")
    p.add_argument("--baseline-rays", type=int, default=40, help="rays for the NumPy baseline (default 40)")
    p.add_argument("--meshes", default=None, help="comma-separated paths or icosphere:L (default: see above)")
    args = p.parse_args(argv)
    import brdfpy

    threads = [int(x) for x in args.threads.split(",")]
    n_rays, repeat, n_base = args.rays, args.repeat, args.baseline_rays
    if args.meshes:
        specs = args.meshes.split(",")
    elif args.quick:
        specs = ["icosphere:4"]
    elif (ASSETS / LARGEST).exists() and (ASSETS / HORSE).exists():
        specs = [str(ASSETS / LARGEST), str(ASSETS / HORSE)]
    else:
        print(f"shared meshes not found under {ASSETS}: icosphere(7) and icosphere(6) instead")
        specs = ["icosphere:7", "icosphere:6"]
    if args.quick:
        n_rays, repeat, n_base = 20_000, 1, 5

    before = brdfpy.get_num_threads()
    result: dict[str, Any] = {
        "benchmark": "ao",
        "machine": {
            "cpus": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
        },
        "loadavg_before": loadavg(),
        "cpu_pressure_before": cpu_pressure(),
        "rays_per_batch": n_rays,
        "repeat": repeat,
        "samples_per_vertex": args.samples,
        "meshes": [],
    }
    print(
        f"load average (1 min) before: {result['loadavg_before']}  cores: {os.cpu_count()}  "
        f"CPU pressure (some, avg10): {result['cpu_pressure_before']} %"
    )
    rng = np.random.default_rng(0)
    try:
        for spec in specs:
            mesh, name = load(spec)
            result["meshes"].append(
                bench_mesh(mesh, name, threads, n_rays, repeat, args.samples, n_base, rng)
            )
    finally:
        brdfpy.set_num_threads(before)
    result["loadavg_after"] = loadavg()
    result["cpu_pressure_after"] = cpu_pressure()
    print(
        f"\nload average (1 min) after: {result['loadavg_after']}  "
        f"CPU pressure (some, avg10): {result['cpu_pressure_after']} %"
    )
    return result


if __name__ == "__main__":
    out = main(sys.argv[1:])
    path = HERE / "results" / "ao.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"wrote {path}")
