"""Samples per second of ``Model.sample`` for every registry model (and a measured table), next to the rate
of ``Model.eval`` on the same number of directions, at each thread count.

``Model.sample`` draws ``N`` samples of one view (``count=N``, counter-based random numbers, one broadcast
view and normal): per sample it builds the shading frame, picks a lobe, draws a direction, evaluates the
mixture density and the model's ``shade`` (so it does at least one ``eval`` of work), and writes 28 bytes.
``Model.eval`` gets ``N`` rows of ``l`` (random, above the surface) with one broadcast ``v`` and ``n``, and
writes 12 bytes per row; ``x eval`` is ``sample rate / eval rate`` (the cost of a sample in evaluations).
Each figure is the median of ``--repeats`` runs after one warm-up; the output arrays are allocated by each
call, as a user's call does.

Run ``python benchmarks/run.py sampling`` (JSON in ``benchmarks/results/sampling.json``) or this file alone.
The machine is shared: the 1-minute load average before and after is recorded with the figures.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import brdfpy
import numpy as np


def median_time(fn: Callable[[], object], repeats: int) -> tuple[float, list[float]]:
    fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times


def models() -> list[tuple[str, brdfpy.Model]]:
    out = [(name, brdfpy.model(name)) for name in brdfpy.models()]
    out.append(("cook_torrance_beckmann", brdfpy.model("cook_torrance", distribution="beckmann")))
    ct = brdfpy.model("cook_torrance", roughness=0.2, kd=0.3)
    out.append(("measured_32x32x64", brdfpy.measured.Tabulated.from_model(ct, (32, 32, 64)).as_model()))
    return out


def bench(n: int, threads: Sequence[int], repeats: int) -> dict[str, Any]:
    load_before = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    rng = np.random.default_rng(0)
    z = rng.uniform(0.0, 1.0, n)
    phi = rng.uniform(0.0, 2 * np.pi, n)
    s = np.sqrt(1 - z * z)
    l = np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1).astype(np.float32)
    v = np.array([0.3, 0.2, 0.9], dtype=np.float32)
    nn = np.array([0.0, 0.0, 1.0], dtype=np.float32)
    t = np.array([1.0, 0.0, 0.0], dtype=np.float32)
    results = []
    default_threads = brdfpy.get_num_threads()
    try:
        for th in threads:
            brdfpy.set_num_threads(th)
            for label, m in models():
                ts, times_s = median_time(lambda m=m: m.sample(v, nn, tangent=t, count=n), repeats)
                te, times_e = median_time(lambda m=m: m.eval(l, v, nn, t), repeats)
                rs, re = n / ts, n / te
                results.append(
                    {
                        "model": label,
                        "params": m.params,
                        "n": n,
                        "threads": th,
                        "samples_per_s": rs,
                        "evals_per_s": re,
                        "x_eval": rs / re,
                        "sample_seconds_all": times_s,
                        "eval_seconds_all": times_e,
                    }
                )
                print(
                    f"{label:24s} threads={th}  sample {rs / 1e6:7.2f} M/s   eval {re / 1e6:7.2f} M/s   "
                    f"x eval {rs / re:5.2f}",
                    flush=True,
                )
    finally:
        brdfpy.set_num_threads(None if default_threads == os.cpu_count() else default_threads)
    return {
        "benchmark": "sampling",
        "description": __doc__.split("\n\n")[0] if __doc__ else "",
        "machine": {
            "cpu_count": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
            "numpy": np.__version__,
            "brdfpy": brdfpy.__version__,
            "loadavg_before": load_before,
            "loadavg_after": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        },
        "settings": {"n": n, "threads": list(threads), "repeats": repeats},
        "results": results,
    }


def main(argv: Sequence[str] | None = None) -> dict[str, Any]:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--n", type=int, default=1_000_000, help="samples per call (default 10^6)")
    p.add_argument("--threads", default="1,2", help="comma-separated thread counts (default 1,2)")
    p.add_argument("--repeats", type=int, default=5, help="timed runs per figure (median; default 5)")
    p.add_argument("--quick", action="store_true", help="tiny sizes: checks that the benchmark runs")
    p.add_argument("--json", default=None, help="also write the results to this file")
    a = p.parse_args(argv)
    if a.quick:
        a.n, a.repeats = 2000, 1
    result = bench(a.n, [int(x) for x in a.threads.split(",")], a.repeats)
    if a.json:
        Path(a.json).write_text(json.dumps(result, indent=2) + "\n")
    return result


if __name__ == "__main__":
    main()
