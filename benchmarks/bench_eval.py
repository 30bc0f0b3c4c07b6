"""Evaluations per second of ``Model.eval`` called from Python on NumPy float32 ``(N, 3)`` arrays.

Compared, in the same run and at the same thread count, with

* the NumPy oracle of ``tests/oracle`` (float64, written independently of the Rust), timed at a smaller N
  and reported per evaluation (``× oracle``);
* a memory-bandwidth floor: NumPy copying the same 48 bytes per evaluation in and out — ``np.copyto`` of the
  three ``(N, 3)`` float32 inputs into preallocated arrays plus writing one ``(N, 3)`` float32 output — the
  faster of one thread and the copy split over as many Python threads as brdfpy uses (NumPy releases the
  GIL while copying) (``% of floor``).

Inputs: random unit normals, ``l`` and ``v`` uniform over the hemisphere of the normal (so that almost every
sample does the full work), seeded. Each figure is the median of ``--repeats`` runs after one warm-up.
``Model.eval`` allocates its output on every call, as a user's call does; that cost is included.

Targets (issue 2): Cook-Torrance (GGX, Smith, Schlick) at N = 10^7 at least 50× the NumPy oracle and at
least 40 % of the floor's rate.

Small calls (issue 8): the fixed cost of one ``Model.eval`` call, in µs, on 1 and 100 rows (float32
``(k, 3)`` arrays; ``(3,)`` vectors for ``v`` and ``n``; and Python lists), with and without ``out=``,
next to NumPy's own fixed cost measured in the same run: one ufunc call on the same arrays
(``np.multiply(l, v)``, which allocates its result as ``Model.eval`` does) and ``np.multiply(l, v,
out=buf)``. Each figure is the best of 5 loops of many calls (the least disturbed by other processes).

Run ``python benchmarks/run.py`` (all benchmarks, JSON in ``benchmarks/results/``) or this file alone.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import brdfpy
import numpy as np
from numpy.typing import NDArray

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from oracle import models as om  # noqa: E402  (the oracle lives with the tests)

F32 = NDArray[np.float32]

#: (label, registry name, parameters) of the benchmarked models.
MODELS: list[tuple[str, str, dict[str, Any]]] = [
    ("lambert", "lambert", {}),
    ("blinn_phong", "blinn_phong", {}),
    (
        "cook_torrance_ggx_smith_schlick",
        "cook_torrance",
        {"distribution": "ggx", "masking": "smith", "fresnel": "schlick", "kd": 0.2, "ks": 0.8},
    ),
]


def directions(n: int, seed: int = 0) -> tuple[F32, F32, F32]:
    """Random unit normals and, for each, ``l`` and ``v`` uniform over its hemisphere (float32, (n, 3))."""
    rng = np.random.default_rng(seed)
    out = []
    normal = None
    for _ in range(3):
        w = rng.standard_normal((n, 3), dtype=np.float32)
        w /= np.linalg.norm(w, axis=1, keepdims=True)
        if normal is None:
            normal = w
        else:
            w *= np.sign(np.einsum("ij,ij->i", w, normal))[:, None]  # flip into the normal's hemisphere
        out.append(w)
    n_, l_, v_ = out
    return l_, v_, n_


def median_time(fn: Callable[[], object], repeats: int) -> tuple[float, list[float]]:
    fn()  # warm-up: first-touch page faults of scratch buffers, thread start-up
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times


def floor_fn(l: F32, v: F32, n: F32, threads: int) -> Callable[[], None]:
    """The bandwidth floor: copy the three inputs and write one output, over ``threads`` threads."""
    dst = [np.empty_like(a) for a in (l, v, n)]
    out = np.empty_like(l)
    for d in (*dst, out):
        d.fill(0)  # fault the pages in now, not while timing
    bounds = np.linspace(0, len(l), threads + 1).astype(int)
    pool = ThreadPoolExecutor(threads) if threads > 1 else None

    def part(k: int) -> None:
        s = slice(bounds[k], bounds[k + 1])
        for d, a in zip(dst, (l, v, n)):
            np.copyto(d[s], a[s])
        out[s] = 0.0

    def run() -> None:
        if pool is None:
            part(0)
        else:
            list(pool.map(part, range(threads)))

    return run


def per_call_us(fn: Callable[[], object], calls: int) -> float:
    """Best of 5 loops of ``calls`` calls, in µs per call."""
    fn()
    best = float("inf")
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        best = min(best, time.perf_counter() - t0)
    return best / calls * 1e6


def small_calls(calls: int) -> list[dict[str, Any]]:
    """The fixed cost of a call: ``Model.eval`` on 1 and 100 rows against NumPy's own per-call cost."""
    m = brdfpy.model("cook_torrance")
    rows = []
    print("-- small calls (1 thread): us per call; NumPy's cost for one ufunc call on the same arrays")
    before = brdfpy.get_num_threads()
    brdfpy.set_num_threads(1)
    try:
        for k in (1, 100):
            l, v, n = directions(k, 7)
            v1, n1 = v[0].copy(), n[0].copy()
            buf = np.empty_like(l)
            ll, vl, nl = l.tolist(), v1.tolist(), n1.tolist()
            numpy_alloc = per_call_us(lambda l=l, v=v: np.multiply(l, v), calls)
            numpy_out = per_call_us(lambda l=l, v=v, b=buf: np.multiply(l, v, out=b), calls)
            cases: list[tuple[str, Callable[[], object]]] = [
                ("eval(l, v, n) (k,3) arrays", lambda l=l, v=v, n=n: m.eval(l, v, n)),
                ("eval(l, v[0], n[0]) (3,) v, n", lambda l=l, v=v1, n=n1: m.eval(l, v, n)),
                ("eval(l, v, n, out=buf)", lambda l=l, v=v, n=n, b=buf: m.eval(l, v, n, out=b)),
                ("eval(lists)", lambda l=ll, v=vl, n=nl: m.eval(l, v, n)),
            ]
            print(f"   k={k:<4d} numpy.multiply {numpy_alloc:6.2f} us, with out= {numpy_out:6.2f} us")
            for label, fn in cases:
                us = per_call_us(fn, calls)
                rows.append(
                    {
                        "rows": k,
                        "call": label,
                        "us_per_call": us,
                        "numpy_multiply_us": numpy_alloc,
                        "numpy_multiply_out_us": numpy_out,
                        "x_numpy_multiply": us / numpy_alloc,
                    }
                )
                print(f"   k={k:<4d} {label:32s} {us:6.2f} us  = {us / numpy_alloc:5.2f} x numpy.multiply")
    finally:
        brdfpy.set_num_threads(None if before == os.cpu_count() else before)
    return rows


def bench(
    sizes: Sequence[int],
    threads: Sequence[int],
    repeats: int,
    oracle_n: int,
    seed: int = 0,
    calls: int = 20_000,
) -> dict[str, Any]:
    results: list[dict[str, Any]] = []
    small = small_calls(calls)
    load_before = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    lo, vo, no = directions(oracle_n, seed + 1)
    oracle: dict[str, float] = {}
    for label, name, params in MODELS:
        m = brdfpy.model(name, **params)
        t, _ = median_time(lambda m=m: om.evaluate(m.name, m.params, lo, vo, no), max(1, repeats // 2))
        oracle[label] = oracle_n / t
    default_threads = brdfpy.get_num_threads()
    try:
        for size in sizes:
            l, v, n = directions(size, seed)
            for th in threads:
                brdfpy.set_num_threads(th)
                # The floor is the faster of NumPy's own single-threaded copy and the copy split over
                # `th` Python threads: threads only count when they help.
                floor_runs = {k: median_time(floor_fn(l, v, n, k), repeats) for k in sorted({1, th})}
                best = min(floor_runs, key=lambda k: floor_runs[k][0])
                t_floor, floor_times = floor_runs[best]
                floor_rate = size / t_floor
                for label, name, params in MODELS:
                    m = brdfpy.model(name, **params)
                    t, times = median_time(lambda m=m, l=l, v=v, n=n: m.eval(l, v, n), repeats)
                    rate = size / t
                    results.append(
                        {
                            "model": label,
                            "name": name,
                            "params": m.params,
                            "n": size,
                            "threads": th,
                            "evals_per_s": rate,
                            "seconds_median": t,
                            "seconds_all": times,
                            "oracle_evals_per_s": oracle[label],
                            "floor_evals_per_s": floor_rate,
                            "floor_seconds_all": floor_times,
                            "floor_threads": best,
                            "x_oracle": rate / oracle[label],
                            "pct_floor": 100.0 * rate / floor_rate,
                        }
                    )
                    print(
                        f"{label:34s} N={size:>9,d} threads={th}  {rate / 1e6:8.1f} M evals/s  "
                        f"x{rate / oracle[label]:7.1f} NumPy oracle ({oracle[label] / 1e6:5.2f} M/s)  "
                        f"{100 * rate / floor_rate:5.1f}% of floor ({floor_rate / 1e6:6.1f} M/s)",
                        flush=True,
                    )
    finally:
        brdfpy.set_num_threads(None if default_threads == os.cpu_count() else default_threads)
    return {
        "benchmark": "eval",
        "description": __doc__.split("\n\n")[0] if __doc__ else "",
        "machine": {
            "cpu_count": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
            "numpy": np.__version__,
            "brdfpy": brdfpy.__version__,
            # Other processes share the cores: the 1-minute load average before and after the timings
            # says how much of the machine the figures had (the machine has cpu_count cores).
            "loadavg_before": load_before,
            "loadavg_after": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        },
        "settings": {
            "sizes": list(sizes),
            "threads": list(threads),
            "repeats": repeats,
            "oracle_n": oracle_n,
        },
        "floor": "np.copyto of three (N,3) float32 inputs + writing one (N,3) float32 output: the faster "
        "of 1 thread and the same number of Python threads as brdfpy (floor_threads says which)",
        "targets": {"model": "cook_torrance_ggx_smith_schlick", "n": 10**7, "x_oracle": 50, "pct_floor": 40},
        "results": results,
        "small_calls": small,
    }


def main(argv: Sequence[str] | None = None) -> dict[str, Any]:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--sizes", default="1000000,10000000", help="comma-separated N (default 10^6,10^7)")
    p.add_argument("--threads", default="1,2", help="comma-separated thread counts (default 1,2)")
    p.add_argument("--repeats", type=int, default=5, help="timed runs per figure (median; default 5)")
    p.add_argument("--oracle-n", type=int, default=1_000_000, help="N for the NumPy oracle (default 10^6)")
    p.add_argument("--quick", action="store_true", help="tiny sizes: checks that the benchmark runs")
    p.add_argument("--json", default=None, help="also write the results to this file")
    a = p.parse_args(argv)
    if a.quick:
        a.sizes, a.threads, a.repeats, a.oracle_n = "2000", "1,2", 1, 1000
    result = bench(
        [int(float(s)) for s in a.sizes.split(",")],
        [int(s) for s in a.threads.split(",")],
        a.repeats,
        a.oracle_n,
        calls=200 if a.quick else 20_000,
    )
    if a.json:
        Path(a.json).write_text(json.dumps(result, indent=2) + "\n")
    return result


if __name__ == "__main__":
    main()
