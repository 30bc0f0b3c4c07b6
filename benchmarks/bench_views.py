"""Speed of every BRDF Explorer view (issue 11) through the Python API, on one thread: the polar slice (360
points), the lobe (64 x 128 directions and its mesh), the θ_h/θ_d slice (512 x 512), the albedo curve (31
incidence angles, the views' quadrature) and the lit sphere (512 x 512, one sample per pixel, with the sky
term and the 8-bit image), for every registry model at its defaults. The budget is 20 ms per view.

Times are wall-clock of the ``brdfpy.views`` call (conversions included); each is the best of ``--repeat``
runs (the least disturbed by other processes; the median is in the JSON too). The machine may be shared: the
1-minute load average before and after is recorded, and figures taken while the load exceeds the cores are
upper bounds.

Run through ``python benchmarks/run.py views`` or directly (``python benchmarks/bench_views.py``).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from typing import Any, Callable

BUDGET_MS = 20.0


def _time(f: Callable[[], Any], repeat: int) -> tuple[float, float, float]:
    """Best and median wall time and the CPU time of the process in the best run [ms]. On one thread the CPU
    time is what the view costs on an idle core; the wall time adds the waits for a core on a busy machine."""
    ts, cpu = [], []
    for _ in range(repeat):
        c0, t0 = time.process_time(), time.perf_counter()
        f()
        ts.append(1e3 * (time.perf_counter() - t0))
        cpu.append(1e3 * (time.process_time() - c0))
    best = min(range(len(ts)), key=ts.__getitem__)
    return ts[best], statistics.median(ts), min(cpu)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    import brdfpy
    from brdfpy import views

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--quick", action="store_true", help="small sizes, one repeat (checks that it runs)")
    p.add_argument("--repeat", type=int, default=7)
    p.add_argument("--threads", type=int, default=1)
    args = p.parse_args(argv)
    repeat = 1 if args.quick else args.repeat
    size = 64 if args.quick else 512
    before = os.getloadavg()[0]
    threads_before = brdfpy.get_num_threads()
    brdfpy.set_num_threads(args.threads)
    rows = []
    try:
        print(
            f"{'model':22} "
            + " ".join(f"{v:>12}" for v in ("polar", "lobe", "slice", "albedo", "sphere"))
            + "  [ms]"
        )
        for name in brdfpy.models():
            m = brdfpy.model(name)
            cases = {
                "polar": lambda m=m: views.polar(m, 30.0, n=360),
                "lobe": lambda m=m: views.lobe(m, 30.0, n_theta=64, n_phi=128),
                "slice": lambda m=m: views.half_diff_slice(m, size=size),
                "albedo": lambda m=m: views.albedo(m),
                "sphere": lambda m=m: views.lit_sphere(m, theta_i=30.0, size=size).rgb,
            }
            row: dict[str, Any] = {"model": name}
            for view, f in cases.items():
                best, median, cpu = _time(f, repeat)
                row[view] = {"best_ms": best, "median_ms": median, "cpu_ms": cpu}
            rows.append(row)
            print(
                f"{name:22} " + " ".join(f"{row[v]['best_ms']:6.1f}/{row[v]['cpu_ms']:<5.1f}" for v in cases)
            )
    finally:
        brdfpy.set_num_threads(threads_before)
    after = os.getloadavg()[0]
    over = [
        (r["model"], v)
        for r in rows
        for v in ("polar", "lobe", "slice", "albedo", "sphere")
        if r[v]["cpu_ms"] > BUDGET_MS
    ]
    print(f"load average {before:.1f} -> {after:.1f}; CPU time over {BUDGET_MS:.0f} ms: {over or 'none'}")
    return {
        "benchmark": "views",
        "threads": args.threads,
        "size": size,
        "budget_ms": BUDGET_MS,
        "loadavg_before": before,
        "loadavg_after": after,
        "results": rows,
        "over_budget": over,
    }


if __name__ == "__main__":
    main()
